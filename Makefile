# Two commands do all set-up on a fresh machine:
#   make run    installs into .venv (first time only) and runs the main job
#   make test   installs into .venv (first time only) and runs the test suite
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
THREADS ?= 2

.PHONY: run test clean-venv

$(STAMP): pyproject.toml constraints.txt
	python3 -m venv $(VENV)
	$(PY) -m pip install --quiet torch==2.13.0
	$(PY) -m pip install --quiet -c constraints.txt -e ".[test]"
	touch $(STAMP)

run: $(STAMP)
	$(VENV)/bin/dolphinfit --threads $(THREADS) demo --out out/demo

test: $(STAMP)
	OMP_NUM_THREADS=1 DOLPHINFIT_THREADS=1 $(PY) -m pytest -q

clean-venv:
	rm -rf $(VENV)
