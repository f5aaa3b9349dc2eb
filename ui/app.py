"""Starting the desktop app: the Qt application, the main window, and the path to open."""

import sys
from pathlib import Path

from PySide6.QtWidgets import QApplication

from ui.gc_guard import GuiThreadGarbageCollector
from ui.main_window import APP_NAME, MainWindow


def application() -> QApplication:
    """The process's QApplication (created on first use, with garbage collection kept on its
    thread: ui/gc_guard.py)."""
    app = QApplication.instance()
    if app is None:
        app = QApplication(sys.argv[:1])
        app.setApplicationName(APP_NAME)
        app.setOrganizationName(APP_NAME)
        GuiThreadGarbageCollector(app)
    return app


def run_app(path: Path | None = None, quit_when_shown: bool = False) -> int:
    """Show the main window (opening ``path`` if given) and run the event loop.

    ``quit_when_shown``: quit once the first frame is on screen (start-up timing).
    """
    app = application()
    window = MainWindow()
    if quit_when_shown:
        window.state.frame_shown.connect(lambda _: app.quit())
    window.show()
    if path is not None:
        window.open_path(path)
    return app.exec()
