"""CoverageStrip: per-frame mask coverage painted along the clip; a press seeks."""

import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtGui import QColor

from dolphinfit.core.project.mask_store import Coverage
from dolphinfit.ui.widgets.coverage_strip import (
    BORDER, COLOURS, LOST, NO_MASKS, VISIBLE, CoverageStrip,
)

NUM_FRAMES, WIDTH_PX = 11, 400  # frame k at x = 40 k with no inset


@pytest.fixture
def strip(qtbot) -> CoverageStrip:
    widget = CoverageStrip()
    qtbot.addWidget(widget)
    widget.resize(WIDTH_PX, widget.height())
    widget.show()
    qtbot.waitExposed(widget)
    return widget


def _coverage() -> Coverage:
    visible = np.ones(NUM_FRAMES, bool)
    visible[4:6] = False
    touches = np.zeros(NUM_FRAMES, bool)
    touches[9] = True
    return Coverage(visible, touches, np.where(visible, 500, 0))


def _colour_at(strip: CoverageStrip, x: int) -> QColor:
    return strip.grab().toImage().pixelColor(x, strip.height() - 2)


def test_a_press_requests_the_frame_under_it(qtbot, strip):
    strip.set_coverage(_coverage())
    strip.set_fit_frames([0, 5, 10])
    strip.set_frame(3)
    with qtbot.waitSignal(strip.frame_requested) as signal:
        qtbot.mousePress(strip, Qt.MouseButton.LeftButton, pos=QPoint(7 * 40 + 12, 8))
    assert signal.args == [7]


def test_states_are_painted_per_frame(strip):
    strip.set_coverage(_coverage())
    for frame_idx, state in ((1, VISIBLE), (4, LOST), (9, BORDER)):
        assert _colour_at(strip, 40 * frame_idx + 10) == COLOURS[state]


def test_without_masks_it_paints_grey(qtbot, strip):
    strip.set_coverage(None)
    strip.grab()  # no frames yet: nothing to draw, no crash
    strip.set_num_frames(NUM_FRAMES)
    strip.set_frame(2)
    assert _colour_at(strip, 130) == COLOURS[NO_MASKS]
    strip.set_coverage(_coverage())
    strip.set_num_frames(NUM_FRAMES + 1)  # another clip: its coverage is unknown
    assert _colour_at(strip, 130) == COLOURS[NO_MASKS]
