# Two commands do all set-up on a fresh machine:
#   make run    installs into .venv (first time only) and opens the app on the sample project
#   make test   installs into .venv (first time only) and runs the test suite
#   make demo   the headless main job (fit the sample clip), for machines without a screen
#   make screenshot   the README's screenshots of the app (under Xvfb when there is no display)
#   make docs   the manual (mkdocs-material) into resources/manual/, warnings as errors; Help → Manual opens it
#   make dist   the wheel and sdist into dist/ (the wheel carries the resources, the network weights and the manual)
#   make check-dist   the wheel installed into a fresh venv, then `dolphinfit --help` and `dolphinfit demo --quick`
#   make bundle   a one-folder desktop program (PyInstaller) in bundle/dolphinfit/, from the wheel
#   make check-bundle   the bundle's --help, its masks of a real image, then the app on the
#                       sample under Xvfb (opens, quits)
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
THREADS ?= 2
TEST_WORKERS ?= 2   # pytest-xdist processes, one torch thread each

.PHONY: run test demo screenshot docs dist check-dist bundle check-bundle clean-venv
DIST_VENV ?= /tmp/dolphinfit-dist-venv
BUNDLE_VENV ?= /tmp/dolphinfit-bundle-venv
BUNDLE_HOME := $(abspath build/bundle-home)
DOCS_STAMP := $(VENV)/.docs-installed

$(STAMP): pyproject.toml constraints.txt
	python3 -m venv $(VENV)
	$(PY) -m pip install --quiet torch==2.13.0
	$(PY) -m pip install --quiet -c constraints.txt -e ".[test]"
	$(PY) -m dolphinfit.core.segment.weights
	touch $(STAMP)

# The manual is built once for Help → Manual; the app opens without it where it cannot be.
run: $(STAMP)
	@test -f resources/manual/index.html || $(MAKE) docs \
	  || echo "make run: the manual could not be built (make docs); the app opens without it"
	$(VENV)/bin/dolphinfit --threads $(THREADS) gui --sample

demo: $(STAMP)
	$(VENV)/bin/dolphinfit --threads $(THREADS) demo --out out/demo

screenshot: $(STAMP)
	$(if $(DISPLAY),,xvfb-run -a -s "-screen 0 1920x1200x24") \
	  $(VENV)/bin/dolphinfit --threads $(THREADS) gui --sample --screenshot docs/app.png

test: $(STAMP)
	$(VENV)/bin/lint-imports
	OMP_NUM_THREADS=1 DOLPHINFIT_THREADS=1 $(PY) -m pytest -q -n $(TEST_WORKERS) --dist worksteal --durations=25

$(DOCS_STAMP): $(STAMP)
	$(PY) -m pip install --quiet -c constraints.txt -e ".[docs]"
	touch $(DOCS_STAMP)

docs: $(DOCS_STAMP)   # MkDocs' notices of its own future silenced; see docs/development.md
	NO_MKDOCS_2_WARNING=1 DISABLE_MKDOCS_2_WARNING=true $(VENV)/bin/mkdocs build --strict --quiet

dist: docs
	rm -rf dist
	$(PY) -m pip install --quiet build
	$(PY) -m build --outdir dist

# Outside the clone (cwd in the fresh venv), so nothing resolves to the repository's folders.
check-dist: dist
	rm -rf $(DIST_VENV) && python3 -m venv $(DIST_VENV)
	$(DIST_VENV)/bin/pip install --quiet torch==2.13.0
	$(DIST_VENV)/bin/pip install --quiet -c constraints.txt dist/*.whl
	cd $(DIST_VENV) && bin/dolphinfit --help > /dev/null
	cd $(DIST_VENV) && ! bin/python -c "import core" 2> /dev/null   # no top-level core, app, ui
	cd $(DIST_VENV) && DOLPHINFIT_CACHE_DIR=$(DIST_VENV)/cache bin/dolphinfit --threads $(THREADS) \
	  demo --quick --out $(DIST_VENV)/demo

# PyInstaller runs in a venv of the wheel (not the editable install, whose import hook it
# cannot follow); the commands are imported by name, so every submodule is collected.
bundle: dist
	rm -rf $(BUNDLE_VENV) bundle build/pyinstaller && python3 -m venv $(BUNDLE_VENV)
	$(BUNDLE_VENV)/bin/pip install --quiet torch==2.13.0
	$(BUNDLE_VENV)/bin/pip install --quiet -c constraints.txt dist/*.whl "pyinstaller>=6.10"
	$(BUNDLE_VENV)/bin/pyinstaller --noconfirm --onedir --name dolphinfit --distpath bundle \
	  --workpath build/pyinstaller --specpath build/pyinstaller --log-level ERROR \
	  --collect-submodules dolphinfit --collect-data dolphinfit packaging/bundle_main.py
	cp packaging/dolphinfit.desktop resources/ui/dolphinfit.svg bundle/dolphinfit/

check-bundle: bundle
	cd /tmp && $(abspath bundle)/dolphinfit/dolphinfit --help > /dev/null
	rm -rf $(BUNDLE_HOME) && mkdir -p $(BUNDLE_HOME)
	bundle/dolphinfit/dolphinfit masks tests/data/real/minke/demo.JPG --auto \
	  --out $(BUNDLE_HOME)/masks > /dev/null   # both networks load and run in the bundle
	$(if $(DISPLAY),,xvfb-run -a -s "-screen 0 1600x1000x24") env \
	  DOLPHINFIT_CACHE_DIR=$(BUNDLE_HOME)/cache DOLPHINFIT_CONFIG_DIR=$(BUNDLE_HOME)/config \
	  bundle/dolphinfit/dolphinfit gui --sample --quit-when-shown

clean-venv:
	rm -rf $(VENV)
