"""Exports of measured frames in a worker thread: every frame measured with the Monte Carlo
(core.project.evaluate), then written with its receipt (core.project.exports), with progress
and cancel. One export at a time."""

import logging
import threading
from collections.abc import Sequence
from pathlib import Path

from PySide6.QtCore import QObject, QRunnable, Qt, QThreadPool, Signal, Slot

from core.errors import InputError
from core.measure.uncertainty import DEFAULT_NUM_DRAWS
from core.progress import Cancelled
from core.project.evaluate import frame_results
from core.project.exports import MediaFrames, export_frames
from core.project.model import MeasurementKey, Project

log = logging.getLogger(__name__)

PROGRESS, FINISHED, FAILED, CANCELLED = "progress", "finished", "failed", "cancelled"


class _Export(QRunnable):
    """Measure, then write; reports through ``report(kind, payload)``."""

    def __init__(self, worker: "ExportWorker", project: Project, project_path: Path,
                 keys: Sequence[MeasurementKey], out_dir: Path, stem: str, receipts: bool,
                 cancel: threading.Event) -> None:
        super().__init__()
        self._worker = worker
        self._args = (project, Path(project_path), list(keys), Path(out_dir), stem, receipts)
        self._cancel = cancel

    def run(self) -> None:
        report = self._worker._report.emit
        project, project_path, keys, out_dir, stem, receipts = self._args
        num_keys = len(keys)  # steps: measuring each frame, then writing each measured one
        try:
            results, skipped = frame_results(
                project, project_path, keys, self._worker.num_draws,
                progress=lambda done, _: report(PROGRESS, (done, 2 * num_keys)),
                cancel=self._cancel)
            with MediaFrames(project, project_path) as frames:
                paths = export_frames(
                    project, results, out_dir, stem, frames if receipts else None,
                    progress=lambda done, total: report(PROGRESS, (num_keys + done,
                                                                   num_keys + total)),
                    cancel=self._cancel)
        except Cancelled:
            report(CANCELLED, None)
        except (InputError, ValueError, OSError) as exc:
            report(FAILED, str(exc))
        except Exception as exc:  # an internal error still reaches the user, as a message
            log.exception("export failed")
            report(FAILED, f"internal error: {exc!r}")
        else:
            report(FINISHED, (paths, skipped + frames.notes))


class ExportWorker(QObject):
    """Runs exports off the GUI thread; signals arrive on the GUI thread."""

    progress = Signal(int, int)           # steps done, steps in all (measure, then write)
    finished = Signal(object, object)     # paths written, list[str] frames left out and why
    failed = Signal(str)                  # why nothing was written
    cancelled = Signal()                  # nothing was written
    _report = Signal(str, object)         # kind, payload (worker → GUI thread)

    def __init__(self, parent: QObject | None = None,
                 num_draws: int = DEFAULT_NUM_DRAWS) -> None:
        super().__init__(parent)
        self.num_draws = num_draws
        self._pool = QThreadPool(self)
        self._pool.setMaxThreadCount(1)
        self._cancel: threading.Event | None = None
        self._report.connect(self._relay, Qt.ConnectionType.QueuedConnection)

    @property
    def is_running(self) -> bool:
        return self._cancel is not None

    def start(self, project: Project, project_path: Path, keys: Sequence[MeasurementKey],
              out_dir: Path, stem: str, receipts: bool = True) -> None:
        """Export the frames ``keys`` of the project saved at ``project_path`` (media and
        altitude files are relative to it) as ``out_dir/STEM_*``; receipts need the media."""
        if self.is_running:
            self.failed.emit("an export is already running")
            return
        self._cancel = threading.Event()
        self._pool.start(_Export(self, project, project_path, keys, out_dir, stem, receipts,
                                 self._cancel))

    def cancel(self) -> None:
        """Stop the running export at the next frame; it removes what it wrote."""
        if self._cancel is not None:
            self._cancel.set()

    def shutdown(self) -> None:
        """Cancel and wait for the export in flight (the window's close)."""
        self.cancel()
        self._pool.waitForDone()

    @Slot(str, object)
    def _relay(self, kind: str, payload: object) -> None:
        if kind == PROGRESS:
            self.progress.emit(*payload)
            return
        self._cancel = None
        if kind == FINISHED:
            self.finished.emit(*payload)
        elif kind == FAILED:
            self.failed.emit(payload)
        else:
            self.cancelled.emit()
