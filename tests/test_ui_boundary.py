"""The app opens without the fitting stack: importing every module of ``ui`` loads no torch
(it costs more than a second of start-up on these machines)."""

import subprocess
import sys

_PROBE = """
import importlib, pkgutil, sys
import dolphinfit.ui as ui
names = [m.name for m in pkgutil.walk_packages(ui.__path__, "dolphinfit.ui.")]
for name in names:
    importlib.import_module(name)
print(len(names), "torch" in sys.modules)
"""


def test_importing_every_ui_module_loads_no_torch():
    out = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                         check=True).stdout.split()
    assert int(out[0]) >= 15
    assert out[1] == "False"
