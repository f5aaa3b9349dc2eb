"""The timeline under the frame view: frame slider, measured-frame marks, mask coverage with
the fit's frames, altitude strip.

Frames are shown as their stored 0-based index. The strips share the slider's column and
place frame k where the slider's handle centre would be, so marks line up with the handle.
"""

from collections.abc import Sequence

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt, Signal
from PySide6.QtGui import (QColor, QMouseEvent, QPainter, QPaintEvent, QPen, QPolygonF)
from PySide6.QtWidgets import QGridLayout, QLabel, QSlider, QStyle, QWidget

from dolphinfit.core.project.mask_store import Coverage
from dolphinfit.ui.widgets.coverage_strip import CoverageStrip
from dolphinfit.ui.widgets.frame_strip import STRIP_BACKGROUND, FrameStrip, PlottedStrip

MARK_COLOUR = QColor(255, 200, 60)
MEASURED_COLOUR = QColor(90, 170, 255)
INTERPOLATED_COLOUR = QColor(185, 210, 235, 120)  # paler than the measured curve
MISSING_COLOUR = QColor(230, 50, 50)
TEXT_COLOUR = QColor(200, 200, 200)
MARK_STRIP_HEIGHT_PX = 12
MARK_HIT_PX = 6  # a press this close to a mark jumps to it
ALTITUDE_STRIP_HEIGHT_PX = 48
PLOT_TOP_PX = 15  # room for the label above the curve
PLOT_BOTTOM_PX = 7  # room for the missing-sample ticks below it


class _MarkStrip(FrameStrip):
    """Ticks at the measured frames; a press near one jumps to it."""

    def __init__(self, inset_px: float, parent: QWidget | None = None) -> None:
        super().__init__(inset_px, MARK_STRIP_HEIGHT_PX, parent)
        self._marks = np.zeros(0, dtype=np.int64)
        self.setToolTip("Measured frames: click one to go there")

    def set_marks(self, frames: Sequence[int]) -> None:
        self._marks = np.unique(np.asarray(frames, dtype=np.int64))
        self.update()

    def paintEvent(self, event: QPaintEvent) -> None:
        painter = QPainter(self)
        painter.fillRect(self.rect(), STRIP_BACKGROUND)
        self._draw_current(painter)
        if self._num_frames:
            painter.setPen(QPen(MARK_COLOUR, 2))
            for x in self.x_of(self._marks):
                painter.drawLine(QPointF(x, 2), QPointF(x, self.height() - 2))

    def mousePressEvent(self, event: QMouseEvent) -> None:
        if event.button() != Qt.MouseButton.LeftButton or not self._marks.size:
            return
        distance = np.abs(self.x_of(self._marks) - event.position().x())
        nearest = int(np.argmin(distance))
        if distance[nearest] <= MARK_HIT_PX:
            self.frame_requested.emit(int(self._marks[nearest]))


class _AltitudeStrip(PlottedStrip):
    """Altitude over the clip: measured samples, interpolated ones lighter, missing ones as red
    ticks, the current frame as a line; pressing or dragging seeks."""

    def __init__(self, inset_px: float, parent: QWidget | None = None) -> None:
        super().__init__(inset_px, ALTITUDE_STRIP_HEIGHT_PX, parent)
        self._altitude_m: np.ndarray | None = None
        self._is_interpolated = np.zeros(0, dtype=bool)
        self._is_missing = np.zeros(0, dtype=bool)
        self._label = ""
        self.setToolTip("Drone altitude per frame: lighter where interpolated, red ticks where "
                        "missing; click or drag to seek")

    def set_altitude(self, altitude_m: np.ndarray | None, is_interpolated: np.ndarray | None,
                     is_missing: np.ndarray | None, label: str) -> None:
        if altitude_m is None:
            self._altitude_m = None
        else:
            self._altitude_m = np.asarray(altitude_m, dtype=np.float64)
            n = len(self._altitude_m)
            self._is_interpolated = _mask(is_interpolated, n, "is_interpolated")
            self._is_missing = _mask(is_missing, n, "is_missing")
        self._label = label
        self.invalidate()

    def draw_plot(self, painter: QPainter) -> None:
        summary = "no altitude"
        if self._altitude_m is not None and self._num_frames:
            shown = np.where(self._is_missing, np.nan, self._altitude_m)
            finite = np.isfinite(shown)
            if finite.any():
                low, high = shown[finite].min(), shown[finite].max()
                summary = f"{low:.1f}–{high:.1f} m"
                self._draw_curve(painter, shown, low, high)
            self._draw_missing(painter)
        painter.setPen(TEXT_COLOUR)
        painter.drawText(QRectF(4, 0, self.width() - 8, PLOT_TOP_PX),
                         Qt.AlignmentFlag.AlignLeft | Qt.AlignmentFlag.AlignVCenter,
                         f"{self._label}  {summary}".strip())

    def _draw_curve(self, painter: QPainter, shown: np.ndarray, low: float, high: float) -> None:
        """Polylines through at most two samples per pixel column, coloured by kind."""
        num = min(len(shown), 2 * max(self.width(), 1))
        idx = np.unique(np.linspace(0, len(shown) - 1, num).round().astype(np.int64))
        bottom = self.height() - PLOT_BOTTOM_PX
        scale = (bottom - PLOT_TOP_PX) / (high - low) if high > low else 0.0
        ys = (np.full(len(idx), (bottom + PLOT_TOP_PX) / 2) if scale == 0
              else bottom - (shown[idx] - low) * scale)
        points = [QPointF(x, y) for x, y in zip(self.x_of(idx), ys)]
        kind = np.where(np.isfinite(shown[idx]), self._is_interpolated[idx], -1)
        edges = np.flatnonzero(np.diff(kind)) + 1
        for start, stop in zip(np.r_[0, edges], np.r_[edges, len(idx)]):
            if kind[start] < 0:
                continue
            if stop < len(idx) and kind[stop] >= 0:
                stop += 1  # join the next run
            colour = INTERPOLATED_COLOUR if kind[start] else MEASURED_COLOUR
            painter.setPen(QPen(colour, 1.5))
            if stop - start == 1:
                painter.drawPoint(points[start])
            else:
                painter.drawPolyline(QPolygonF(points[start:stop]))

    def _draw_missing(self, painter: QPainter) -> None:
        missing = np.flatnonzero(self._is_missing)
        if not missing.size:
            return
        top = self.height() - PLOT_BOTTOM_PX + 2
        for x in np.unique(np.floor(self.x_of(missing))):
            painter.fillRect(QRectF(x, top, 1, PLOT_BOTTOM_PX - 2), MISSING_COLOUR)


def _mask(values: np.ndarray | None, length: int, name: str) -> np.ndarray:
    """A boolean mask of ``length`` (all False for None); ValueError on another length."""
    if values is None:
        return np.zeros(length, dtype=bool)
    values = np.asarray(values, dtype=bool)
    if values.shape != (length,):
        raise ValueError(f"{name} has shape {values.shape}, expected ({length},)")
    return values


class Timeline(QWidget):
    """Slider over the clip's frames with a frame/time readout, marks and altitude strip.

    User actions emit ``frame_requested``; ``set_frame`` (the frame now shown) updates the
    widgets without emitting. The slider takes no keyboard focus: frame keys are app shortcuts.
    """

    frame_requested = Signal(int)

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._num_frames = 0
        self._fps = 1.0
        self._slider = QSlider(Qt.Orientation.Horizontal)
        self._slider.setFocusPolicy(Qt.FocusPolicy.NoFocus)
        self._slider.setEnabled(False)
        self._label = QLabel()
        self._label.setToolTip("Frame index as stored (0-based), of the clip's 0 … last · "
                               "time from the first frame (index / fps)")
        inset = self._slider.style().pixelMetric(QStyle.PixelMetric.PM_SliderLength, None,
                                                 self._slider) / 2
        self._marks = _MarkStrip(inset)
        self._coverage = CoverageStrip(inset)
        self._altitude = _AltitudeStrip(inset)
        layout = QGridLayout(self)
        layout.setContentsMargins(4, 2, 4, 2)
        layout.setVerticalSpacing(2)
        layout.addWidget(self._slider, 0, 0)
        layout.addWidget(self._label, 0, 1)
        layout.addWidget(self._marks, 1, 0)
        layout.addWidget(self._coverage, 2, 0)
        layout.addWidget(self._altitude, 3, 0)
        layout.setColumnStretch(0, 1)
        self._slider.valueChanged.connect(self.frame_requested)
        for strip in (self._marks, self._coverage, self._altitude):
            strip.frame_requested.connect(self.frame_requested)
        self._update_label(0)

    def set_clip(self, num_frames: int, fps: float) -> None:
        """A clip of ``num_frames`` frames at ``fps``; the current frame becomes 0."""
        self._num_frames = num_frames
        self._fps = fps
        self._slider.setEnabled(num_frames > 0)
        self._slider.blockSignals(True)
        self._slider.setRange(0, max(num_frames - 1, 0))
        self._slider.blockSignals(False)
        for strip in (self._marks, self._coverage, self._altitude):
            strip.set_num_frames(num_frames)
        metrics = self._label.fontMetrics()  # wide enough for the last frame: no jitter
        self._label.setMinimumWidth(metrics.horizontalAdvance(self._label_text(num_frames - 1))
                                    + metrics.averageCharWidth())
        self.set_frame(0)

    def set_frame(self, frame_idx: int) -> None:
        """Show ``frame_idx`` as current, without emitting ``frame_requested``."""
        if not self._slider.isSliderDown():  # don't fight the user's drag
            self._slider.blockSignals(True)
            self._slider.setValue(frame_idx)
            self._slider.blockSignals(False)
        for strip in (self._marks, self._coverage, self._altitude):
            strip.set_frame(frame_idx)
        self._update_label(frame_idx)

    def set_marks(self, frames: Sequence[int]) -> None:
        """Mark the measured frames (0-based indices)."""
        self._marks.set_marks(frames)

    def set_coverage(self, coverage: Coverage | None) -> None:
        """Per-frame mask coverage of the clip (None: no masks)."""
        self._coverage.set_coverage(coverage)

    def set_fit_frames(self, frames: Sequence[int]) -> None:
        """The frames the fit will use, ticked on the coverage strip."""
        self._coverage.set_fit_frames(frames)

    def set_altitude(self, altitude_m: np.ndarray | None, is_interpolated: np.ndarray | None,
                     is_missing: np.ndarray | None, label: str) -> None:
        """Per-frame altitude (metres, NaN allowed; sample k is frame k) and its flags."""
        self._altitude.set_altitude(altitude_m, is_interpolated, is_missing, label)

    def _update_label(self, frame_idx: int) -> None:
        self._label.setText(self._label_text(frame_idx) if self._num_frames else "no clip")

    def _label_text(self, frame_idx: int) -> str:
        return f"frame {frame_idx} of 0–{self._num_frames - 1} · {frame_idx / self._fps:.2f} s"
