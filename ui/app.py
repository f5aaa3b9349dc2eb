"""The desktop app's Qt application: one per process, named, with garbage collection kept
on its thread."""

import sys

from PySide6.QtGui import QIcon
from PySide6.QtWidgets import QApplication

from dolphinfit.core.resources import resource_path

from dolphinfit.ui.gc_guard import GuiThreadGarbageCollector

APP_NAME = "dolphinfit"


def application() -> QApplication:
    """The process's QApplication (created on first use, with garbage collection kept on its
    thread: ui/gc_guard.py)."""
    app = QApplication.instance()
    if app is None:
        app = QApplication(sys.argv[:1])
        app.setApplicationName(APP_NAME)
        app.setOrganizationName(APP_NAME)
        app.setWindowIcon(QIcon(str(resource_path("ui", "dolphinfit.svg"))))
        GuiThreadGarbageCollector(app)
    return app
