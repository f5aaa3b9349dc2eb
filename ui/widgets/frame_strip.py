"""A strip under the frame slider whose x axis is the clip's frames (the timeline's marks,
mask coverage and altitude)."""

import numpy as np
from PySide6.QtCore import QPointF, Qt, Signal
from PySide6.QtGui import (QColor, QMouseEvent, QPainter, QPaintEvent, QPen, QPixmap,
                           QResizeEvent)
from PySide6.QtWidgets import QSizePolicy, QWidget

STRIP_BACKGROUND = QColor(40, 40, 40)
CURRENT_COLOUR = QColor(240, 240, 240)


class FrameStrip(QWidget):
    """A strip whose x axis is the clip's frames, aligned with the slider's handle centre."""

    frame_requested = Signal(int)

    def __init__(self, inset_px: float, height_px: int, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._inset_px = inset_px
        self._num_frames = 0
        self._frame = 0
        self.setFixedHeight(height_px)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)

    def set_num_frames(self, num_frames: int) -> None:
        self._num_frames = num_frames
        self.update()

    def set_frame(self, frame_idx: int) -> None:
        self._frame = frame_idx
        self.update()

    def x_of(self, frame_idx: np.ndarray | int) -> np.ndarray:
        """Widget x of frame(s) ``frame_idx``."""
        span = self.width() - 2 * self._inset_px
        return self._inset_px + span * np.asarray(frame_idx) / max(self._num_frames - 1, 1)

    def frame_at(self, x: float) -> int:
        """The frame nearest to widget x, clamped to the clip."""
        span = max(self.width() - 2 * self._inset_px, 1.0)
        frame_idx = round((x - self._inset_px) / span * (self._num_frames - 1))
        return min(max(frame_idx, 0), max(self._num_frames - 1, 0))

    def _draw_current(self, painter: QPainter) -> None:
        if self._num_frames:
            painter.setPen(QPen(CURRENT_COLOUR, 1))
            x = float(self.x_of(self._frame))
            painter.drawLine(QPointF(x, 0), QPointF(x, self.height()))


class PlottedStrip(FrameStrip):
    """A strip whose static picture is drawn once per data or size change into a pixmap,
    with the current frame drawn over it; pressing or dragging seeks. Subclasses draw the
    picture in ``draw_plot`` and call ``invalidate`` when their data change."""

    def __init__(self, inset_px: float, height_px: int, parent: QWidget | None = None) -> None:
        super().__init__(inset_px, height_px, parent)
        self._plot: QPixmap | None = None

    def draw_plot(self, painter: QPainter) -> None:
        """Draw the static picture over the background."""
        raise NotImplementedError

    def invalidate(self) -> None:
        self._plot = None
        self.update()

    def set_num_frames(self, num_frames: int) -> None:
        super().set_num_frames(num_frames)
        self.invalidate()

    def resizeEvent(self, event: QResizeEvent) -> None:  # noqa: N802 (Qt's name)
        self.invalidate()

    def paintEvent(self, event: QPaintEvent) -> None:  # noqa: N802 (Qt's name)
        if self._plot is None:
            ratio = self.devicePixelRatioF()
            self._plot = QPixmap(self.size() * ratio)
            self._plot.setDevicePixelRatio(ratio)
            self._plot.fill(STRIP_BACKGROUND)
            plot_painter = QPainter(self._plot)
            plot_painter.setRenderHint(QPainter.RenderHint.Antialiasing)
            self.draw_plot(plot_painter)
            plot_painter.end()
        painter = QPainter(self)
        painter.drawPixmap(0, 0, self._plot)
        self._draw_current(painter)

    def mousePressEvent(self, event: QMouseEvent) -> None:  # noqa: N802 (Qt's name)
        if event.button() == Qt.MouseButton.LeftButton:
            self._seek(event.position().x())

    def mouseMoveEvent(self, event: QMouseEvent) -> None:  # noqa: N802 (Qt's name)
        if event.buttons() & Qt.MouseButton.LeftButton:
            self._seek(event.position().x())

    def _seek(self, x: float) -> None:
        if self._num_frames:
            self.frame_requested.emit(self.frame_at(x))
