"""A strip under the timeline showing, per frame, what the clip's masks say: the animal
visible (green), lost (red), touching the frame's border (orange), or no masks at all (grey);
ticks mark the frames the fit will use. Pressing or dragging seeks.
"""

from collections.abc import Sequence

import numpy as np
from PySide6.QtCore import QRectF
from PySide6.QtGui import QColor, QPainter
from PySide6.QtWidgets import QWidget

from dolphinfit.core.project.mask_store import Coverage
from dolphinfit.ui.widgets.frame_strip import PlottedStrip

NO_MASKS, VISIBLE, LOST, BORDER = range(4)
COLOURS = {NO_MASKS: QColor(90, 90, 90), VISIBLE: QColor(60, 190, 90),
           LOST: QColor(220, 60, 60), BORDER: QColor(245, 150, 40)}
FIT_TICK_COLOUR = QColor(240, 240, 240)
STRIP_HEIGHT_PX = 14
TICK_HEIGHT_PX = 4  # fit-frame ticks along the top edge
BAND_TOP_PX = TICK_HEIGHT_PX + 1


class CoverageStrip(PlottedStrip):
    """Per-frame mask coverage, the fit's frames and the current frame; ``frame_requested``
    on a press or drag. ``inset_px``: where frame 0 sits (the slider's half handle length
    when placed under it, as the timeline's strips)."""

    def __init__(self, inset_px: float = 0.0, parent: QWidget | None = None) -> None:
        super().__init__(inset_px, STRIP_HEIGHT_PX, parent)
        self._states: np.ndarray | None = None  # (T,) NO_MASKS…BORDER; None: no masks
        self._fit_frames = np.zeros(0, dtype=np.int64)
        self.setToolTip("Masks per frame: green visible, red lost, orange touching the "
                        "border, grey none; ticks: frames the fit uses. Click to seek")

    def set_coverage(self, coverage: Coverage | None) -> None:
        """The clip's mask coverage (its frame count becomes the strip's); None: no masks."""
        if coverage is None:
            self._states = None
        else:
            self._states = np.where(coverage.touches_border, BORDER,
                                    np.where(coverage.visible, VISIBLE, LOST))
            super().set_num_frames(coverage.num_frames)
        self.invalidate()

    def set_fit_frames(self, frames: Sequence[int]) -> None:
        """The frames (0-based) the fit will use."""
        self._fit_frames = np.unique(np.asarray(frames, dtype=np.int64))
        self.invalidate()

    def set_num_frames(self, num_frames: int) -> None:
        """The clip's frame count; coverage of another count is dropped."""
        if self._states is not None and len(self._states) != num_frames:
            self._states = None
        super().set_num_frames(num_frames)
        self.invalidate()

    def draw_plot(self, painter: QPainter) -> None:
        if self._num_frames:
            self._draw_states(painter)
            for x in np.unique(np.floor(self.x_of(self._fit_frames))):
                painter.fillRect(QRectF(x, 0, 1, TICK_HEIGHT_PX), FIT_TICK_COLOUR)

    def _draw_states(self, painter: QPainter) -> None:
        """One band per run of frames in the same state, frame k spanning k ± ½."""
        states = (np.full(self._num_frames, NO_MASKS) if self._states is None
                  else self._states)
        edges = np.flatnonzero(np.diff(states)) + 1
        starts, stops = np.r_[0, edges], np.r_[edges, len(states)]
        lefts, rights = self.x_of(starts - 0.5), self.x_of(stops - 0.5)
        height = self.height() - BAND_TOP_PX
        for start, left, right in zip(starts, lefts, rights):
            painter.fillRect(QRectF(left, BAND_TOP_PX, right - left, height),
                             COLOURS[int(states[start])])
