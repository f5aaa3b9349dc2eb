"""A cancellable progress dialog over a JobWorker's job: shown after half a second, its bar
and text following the job's progress, its Cancel the worker's, closed when the job ends."""

from PySide6.QtWidgets import QProgressDialog, QWidget

from dolphinfit.core.progress import Progress
from dolphinfit.ui.workers.job_worker import JobWorker

SHOW_AFTER_MS = 500


class JobProgress:
    """Follows ``worker``: ``start()`` after each job is started; closes itself when it
    finishes, fails or is cancelled."""

    def __init__(self, worker: JobWorker, title: str, text: str, parent: QWidget) -> None:
        self._worker, self._title, self._text, self._parent = worker, title, text, parent
        self._dialog: QProgressDialog | None = None
        worker.progress.connect(self._on_progress)
        for ended in (worker.finished, worker.failed, worker.cancelled):
            ended.connect(self.close)

    def start(self) -> None:
        self.close()
        self._dialog = QProgressDialog(self._text, "Cancel", 0, 0, self._parent)
        self._dialog.setWindowTitle(self._title)
        self._dialog.setMinimumDuration(SHOW_AFTER_MS)
        self._dialog.canceled.connect(self._worker.cancel)

    def close(self, *_: object) -> None:
        if self._dialog is not None:
            self._dialog.reset()
            self._dialog.deleteLater()
            self._dialog = None

    def _on_progress(self, progress: Progress) -> None:
        if self._dialog is not None:
            self._dialog.setMaximum(progress.total)
            self._dialog.setValue(progress.step)
            self._dialog.setLabelText(f"{progress.stage}: {progress.message}")
