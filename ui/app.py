"""The desktop app's Qt application: one per process, named, with garbage collection kept
on its thread, and the modules that scipy looks up imported on its thread.

scipy's array-API layer (array_api_compat) asks ``sys.modules`` for torch, CuPy, JAX, Dask
and sparse on every call and reads a class off the module it finds there. A module that a
worker is still importing is in ``sys.modules`` half made, so a scipy call on the GUI thread
at that moment fails (issue 53: ``partially initialized module 'torch' has no attribute
'Tensor'``). Of those modules the app's workers import only torch (the CUDA probe, fits,
masks), so torch is imported here, before any worker starts, and is whole from then on.
"""

import importlib
import sys

from PySide6.QtGui import QIcon
from PySide6.QtWidgets import QApplication

from dolphinfit.core.resources import resource_path

from dolphinfit.ui.gc_guard import GuiThreadGarbageCollector

APP_NAME = "dolphinfit"
PROBED_BY_SCIPY = ("torch",)   # those of scipy's probed modules that the app's workers import


def application() -> QApplication:
    """The process's QApplication (created on first use, with garbage collection kept on its
    thread: ui/gc_guard.py, and ``PROBED_BY_SCIPY`` imported: module doc)."""
    app = QApplication.instance()
    if app is None:
        for name in PROBED_BY_SCIPY:
            importlib.import_module(name)
        app = QApplication(sys.argv[:1])
        app.setApplicationName(APP_NAME)
        app.setOrganizationName(APP_NAME)
        app.setWindowIcon(QIcon(str(resource_path("ui", "dolphinfit.svg"))))
        GuiThreadGarbageCollector(app)
    return app
