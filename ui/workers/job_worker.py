"""One long core job at a time in a worker thread, with the core progress/cancel contract
(core/progress.py) carried to the GUI thread by signals: progress, finished, failed,
cancelled. The exports and the fit run on it."""

import threading
from collections.abc import Callable
from typing import Any

from PySide6.QtCore import QObject, QRunnable, Qt, QThreadPool, Signal, Slot

from dolphinfit.core.progress import Cancelled, ProgressCallback
from dolphinfit.ui.workers.background import guarded

PROGRESS, FINISHED, FAILED, CANCELLED = "progress", "finished", "failed", "cancelled"
DEVICE_SETTING = "Edit → Compute device"   # where the jobs' device is chosen, named in errors
Job = Callable[[ProgressCallback, threading.Event], Any]  # (progress, cancel) → result


class _Run(QRunnable):
    def __init__(self, job: Job, report: Callable[[str, object], None],
                 cancel: threading.Event) -> None:
        super().__init__()
        self._job, self._report, self._cancel = job, report, cancel

    def run(self) -> None:
        report = self._report
        try:
            ok, value = guarded(lambda: self._job(lambda progress: report(PROGRESS, progress),
                                                  self._cancel))
        except Cancelled:
            report(CANCELLED, None)
        else:
            report(FINISHED if ok else FAILED, value)


class JobWorker(QObject):
    """Runs one job at a time; every signal arrives on the GUI thread."""

    progress = Signal(object)      # core.progress.Progress
    finished = Signal(object)      # the job's result
    failed = Signal(str)           # why it stopped
    cancelled = Signal()           # the job raised Cancelled
    _report = Signal(str, object)  # kind, payload (worker → GUI thread)

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self._pool = QThreadPool(self)
        self._pool.setMaxThreadCount(1)
        self._cancel: threading.Event | None = None
        self._report.connect(self._relay, Qt.ConnectionType.QueuedConnection)

    @property
    def is_running(self) -> bool:
        return self._cancel is not None

    def run_job(self, job: Job) -> bool:
        """Start ``job(progress, cancel)``; False (and a failed signal) if one is running."""
        if self.is_running:
            self.failed.emit("a job of this kind is already running")
            return False
        self._cancel = threading.Event()
        self._pool.start(_Run(job, self._report.emit, self._cancel))
        return True

    def cancel(self) -> None:
        """Ask the running job to stop (it checks between units of work)."""
        if self._cancel is not None:
            self._cancel.set()

    def shutdown(self) -> None:
        """Cancel and wait for the job in flight (the window's close)."""
        self.cancel()
        self._pool.waitForDone()

    @Slot(str, object)
    def _relay(self, kind: str, payload: object) -> None:
        if kind == PROGRESS:
            self.progress.emit(payload)
            return
        self._cancel = None
        if kind == FINISHED:
            self.finished.emit(payload)
        elif kind == FAILED:
            self.failed.emit(payload)
        else:
            self.cancelled.emit()
