"""The app's answer to an exception that no code caught (a slot that raised: PySide6 hands it
to ``sys.excepthook``): a crash report with the last actions (core.crash_report), the unsaved
work written to the project's autosave so the next open offers it back, and the user told
both paths and what to do. The app goes on running: the failed action did not happen, the
rest of the session is intact. A hard crash (a fault in a native library) bypasses Python;
faulthandler writes its stack to the log folder's fault log instead."""

import faulthandler
import sys
import traceback
from collections.abc import Callable, Sequence
from pathlib import Path
from types import TracebackType

from dolphinfit.core.crash_report import open_fault_log, write_crash_report
from dolphinfit.core.project.project_file import autosave_path
from dolphinfit.ui.state.project_model import ProjectModel


class CrashHandler:
    """Installed as ``sys.excepthook`` while the app runs (module doc). ``tell`` shows the
    report's path (None where it could not be written) and what became of the work."""

    def __init__(self, model: ProjectModel, recent_actions: Sequence[str],
                 tell: Callable[[Path | None, str], None]) -> None:
        self.model = model
        self.recent_actions = recent_actions
        self.tell = tell
        self._previous = sys.excepthook
        self._faults = None
        self._handling = False

    def install(self) -> None:
        self._previous = sys.excepthook
        sys.excepthook = self.handle
        self._faults = open_fault_log()
        faulthandler.enable(self._faults)

    def uninstall(self) -> None:
        sys.excepthook = self._previous
        if self._faults is not None:
            faulthandler.disable()
            self._faults.close()
            self._faults = None

    def handle(self, kind: type[BaseException], error: BaseException,
               trace: TracebackType | None) -> None:
        if issubclass(kind, KeyboardInterrupt) or self._handling:  # a crash while telling
            self._previous(kind, error, trace)
            return
        self._handling = True
        try:
            traceback.print_exception(kind, error, trace)
            try:
                report = write_crash_report(error.with_traceback(trace), "the app",
                                            list(self.recent_actions))
            except OSError:
                report = None
            self.tell(report, self.work_kept())
        finally:
            self._handling = False

    def work_kept(self) -> str:
        """Write the unsaved work to the autosave and say where the work is."""
        path = self.model.path
        if path is None:
            return "No project was open, so no work was lost."
        if not self.model.is_dirty:
            return f"Your work is saved in {path}; nothing was lost."
        self.model.write_autosave()
        kept = autosave_path(path)
        if not kept.exists():
            return (f"Your unsaved work could not be written to {kept}: save the project "
                    f"under another name (File → Save project as…) now.")
        return (f"Your unsaved work was written to {kept}. Save the project now; if dolphinfit "
                f"closes first, opening {path.name} again offers that work back.")
