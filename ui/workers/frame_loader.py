"""Frame decoding in a worker thread that serves only the newest request.

Held arrow keys and slider drags request frames faster than they decode: requests made while
the worker is busy replace one another, and the worker decodes only the newest when it is free.
"""

import threading
from dataclasses import dataclass

import numpy as np
from PySide6.QtCore import QObject, QThread, Signal, Slot
from PySide6.QtGui import QImage

from dolphinfit.core.io.frame_source import FrameSource


def rgb_to_qimage(rgb: np.ndarray) -> QImage:
    """A QImage (Format_RGB888) owning a copy of an (H, W, 3) uint8 RGB frame."""
    if rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.dtype != np.uint8:
        raise ValueError(f"expected an (H, W, 3) uint8 RGB frame, got {rgb.shape} {rgb.dtype}")
    rgb = np.ascontiguousarray(rgb)
    height, width = rgb.shape[:2]
    return QImage(rgb.data, width, height, 3 * width, QImage.Format.Format_RGB888).copy()


@dataclass(frozen=True, slots=True)
class _Job:
    """One frame to decode, tagged with the source generation it was asked of."""

    generation: int
    source: FrameSource
    frame_idx: int


class _Mailbox:
    """The newest pending job and whether the worker is busy, shared under one lock."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._pending: _Job | None = None
        self._busy = False

    def post(self, job: _Job | None) -> bool:
        """Replace the pending job; True if the worker is idle and must be woken."""
        with self._lock:
            self._pending = job
            wake = job is not None and not self._busy
            self._busy |= wake
            return wake

    def take(self) -> _Job | None:
        """The pending job, or None (and the worker marked idle) if there is none."""
        with self._lock:
            job, self._pending = self._pending, None
            self._busy = job is not None
            return job


class _Worker(QObject):
    """Lives in the decoding thread; decodes jobs until the mailbox is empty."""

    decoded = Signal(int, int, object)  # generation, frame index, RGB frame
    errored = Signal(int, int, str)  # generation, frame index, message

    def __init__(self, mailbox: _Mailbox) -> None:
        super().__init__()
        self._mailbox = mailbox

    @Slot()
    def drain(self) -> None:
        while (job := self._mailbox.take()) is not None:
            try:
                rgb = job.source.frame(job.frame_idx)
            except Exception as exc:  # relayed to the GUI thread, whatever the source raised
                self.errored.emit(job.generation, job.frame_idx, str(exc) or type(exc).__name__)
            else:
                self.decoded.emit(job.generation, job.frame_idx, rgb)


class FrameLoader(QObject):
    """Decodes requested frames off the GUI thread; results arrive on the GUI thread.

    ``request(i)`` is cheap: while a decode runs, later requests replace one another and only
    the newest is decoded next. Results of a source replaced by ``set_source`` are dropped.
    Call ``shutdown()`` when the owner closes.
    """

    frame_ready = Signal(int, object)  # frame index, (H, W, 3) uint8 RGB read-only ndarray
    failed = Signal(int, str)  # frame index, error message
    _wake = Signal()

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self._source: FrameSource | None = None
        self._generation = 0
        self._mailbox = _Mailbox()
        self._thread = QThread()
        self._thread.setObjectName("FrameLoader")
        self._worker = _Worker(self._mailbox)
        self._worker.moveToThread(self._thread)
        self._wake.connect(self._worker.drain)
        self._worker.decoded.connect(self._on_decoded)
        self._worker.errored.connect(self._on_errored)
        self._thread.finished.connect(self._worker.deleteLater)
        self._thread.start()

    def set_source(self, source: FrameSource | None) -> None:
        """Serve frames of ``source`` from now on; pending and in-flight results are dropped."""
        self._source = source
        self._generation += 1
        self._mailbox.post(None)

    def request(self, frame_idx: int) -> None:
        """Ask for frame ``frame_idx``; ignored without a source or after ``shutdown``."""
        if self._source is None or not self._thread.isRunning():
            return
        if self._mailbox.post(_Job(self._generation, self._source, int(frame_idx))):
            self._wake.emit()

    def shutdown(self) -> None:
        """Drop pending requests and join the thread (after the decode in flight, if any)."""
        self.set_source(None)
        self._thread.quit()
        self._thread.wait()

    @Slot(int, int, object)
    def _on_decoded(self, generation: int, frame_idx: int, rgb: np.ndarray) -> None:
        if generation == self._generation:
            self.frame_ready.emit(frame_idx, rgb)

    @Slot(int, int, str)
    def _on_errored(self, generation: int, frame_idx: int, message: str) -> None:
        if generation == self._generation:
            self.failed.emit(frame_idx, message)
