"""The engine stays headless: importing all of ``core`` loads no GUI or 3D-view module."""

import subprocess
import sys

FORBIDDEN = ("PySide6", "pyvista", "pyvistaqt", "vtk", "vtkmodules", "qtpy")

_PROBE = f"""
import importlib, pkgutil, sys
import dolphinfit.core as core
names = [m.name for m in pkgutil.walk_packages(core.__path__, "dolphinfit.core.")]
for name in names:
    importlib.import_module(name)
loaded = sorted({{m.split(".")[0] for m in sys.modules}} & set({FORBIDDEN!r}))
print(len(names), ",".join(loaded))
"""


def test_importing_every_core_module_loads_no_gui_or_vtk():
    """A fresh interpreter imports every module under core/ and none of Qt, pyvista or vtk."""
    out = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                         check=True).stdout.split()
    assert int(out[0]) >= 10
    assert out[1:] == []
