"""Timeline (slider, marks, altitude strip) and Playback."""

import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtWidgets import QLabel, QSlider

from dolphinfit.ui.controllers.playback import Playback
from dolphinfit.ui.widgets.timeline import MISSING_COLOUR, Timeline, _AltitudeStrip, _MarkStrip

NUM_FRAMES, FPS = 1500, 10.0
TIMEOUT_MS = 2000


@pytest.fixture
def timeline(qtbot):
    widget = Timeline()
    qtbot.addWidget(widget)
    widget.resize(900, 120)
    widget.show()
    qtbot.waitExposed(widget)
    widget.set_clip(NUM_FRAMES, FPS)
    return widget


def test_set_frame_updates_the_slider_and_readout_without_requesting(qtbot, timeline):
    with qtbot.assertNotEmitted(timeline.frame_requested):
        timeline.set_frame(123)
    assert timeline.findChild(QSlider).value() == 123
    assert timeline.findChild(QLabel).text() == "frame 123 of 0–1499 · 12.30 s"
    assert "0-based" in timeline.findChild(QLabel).toolTip()


def test_moving_the_slider_requests_its_frame(qtbot, timeline):
    with qtbot.waitSignal(timeline.frame_requested, timeout=TIMEOUT_MS) as blocker:
        timeline.findChild(QSlider).setValue(400)
    assert blocker.args == [400]


def test_a_press_near_a_mark_jumps_to_it(qtbot, timeline):
    timeline.set_marks([700, 10, 1400, 700])
    strip = timeline.findChild(_MarkStrip)
    x = round(float(strip.x_of(700)))
    with qtbot.waitSignal(timeline.frame_requested, timeout=TIMEOUT_MS) as blocker:
        qtbot.mouseClick(strip, Qt.MouseButton.LeftButton, pos=QPoint(x + 3, 5))
    assert blocker.args == [700]
    with qtbot.assertNotEmitted(timeline.frame_requested):
        qtbot.mouseClick(strip, Qt.MouseButton.LeftButton, pos=QPoint(x + 60, 5))


def test_pressing_and_dragging_on_the_altitude_strip_seeks(qtbot, timeline):
    strip = timeline.findChild(_AltitudeStrip)
    requested: list[int] = []
    timeline.frame_requested.connect(requested.append)
    x0, x1 = (round(float(strip.x_of(frame))) for frame in (300, 900))
    qtbot.mousePress(strip, Qt.MouseButton.LeftButton, pos=QPoint(x0, 20))
    qtbot.mouseMove(strip, QPoint(x1, 20))
    qtbot.mouseRelease(strip, Qt.MouseButton.LeftButton, pos=QPoint(x1, 20))
    assert requested[0] == pytest.approx(300, abs=2)
    assert requested[-1] == pytest.approx(900, abs=2)
    assert strip.frame_at(strip.x_of(NUM_FRAMES - 1)) == NUM_FRAMES - 1
    assert strip.frame_at(-50) == 0


def test_the_altitude_strip_draws_nan_interpolated_and_missing_samples(timeline):
    altitude = 18.2 + 0.7 * np.sin(np.linspace(0, 3, NUM_FRAMES))
    interpolated = np.zeros(NUM_FRAMES, dtype=bool)
    interpolated[500:600] = True
    missing = np.zeros(NUM_FRAMES, dtype=bool)
    missing[1000:1100] = True
    altitude[1000:1100] = np.nan
    altitude[1200] = np.nan  # an isolated gap
    timeline.set_altitude(altitude, interpolated, missing, "SRT altitude")
    strip = timeline.findChild(_AltitudeStrip)
    image = strip.grab().toImage()
    bottom = strip.height() - 2
    red = [image.pixelColor(x, bottom) == MISSING_COLOUR for x in range(strip.width())]
    first, last = (round(float(strip.x_of(frame))) for frame in (1000, 1099))
    assert all(red[first + 1:last]) and not red[first - 20] and not red[last + 20]
    timeline.set_altitude(np.full(NUM_FRAMES, np.nan), None, None, "SRT altitude")
    strip.grab()
    timeline.set_altitude(None, None, None, "")
    strip.grab()
    with pytest.raises(ValueError):
        timeline.set_altitude(altitude, interpolated[:10], None, "SRT altitude")


def test_playback_asks_for_the_next_frame_only_after_the_last_was_shown(qtbot):
    playback = Playback()
    playback.set_clip(4, 200.0)
    requested: list[int] = []
    playback.frame_requested.connect(requested.append)
    with qtbot.waitSignal(playback.playing_changed, timeout=TIMEOUT_MS) as blocker:
        playback.toggle()
    assert blocker.args == [True] and playback.is_playing
    assert requested == [1]
    with qtbot.assertNotEmitted(playback.frame_requested, wait=50):  # ten ticks
        pass
    with qtbot.waitSignal(playback.frame_requested, timeout=TIMEOUT_MS) as blocker:
        playback.frame_shown(1)
    assert blocker.args == [2]
    with qtbot.waitSignal(playback.frame_requested, timeout=TIMEOUT_MS) as blocker:
        playback.frame_shown(2)
    assert blocker.args == [3]
    with qtbot.waitSignal(playback.playing_changed, timeout=TIMEOUT_MS) as blocker:
        playback.frame_shown(3)  # the last frame: playback stops
    assert blocker.args == [False] and not playback.is_playing


def test_playback_toggles_off_and_restarts_from_the_start_at_the_end(qtbot):
    playback = Playback()
    playback.set_clip(10, 25.0)
    playback.frame_shown(9)
    with qtbot.waitSignal(playback.frame_requested, timeout=TIMEOUT_MS) as blocker:
        playback.toggle()
    assert blocker.args == [0]
    with qtbot.waitSignal(playback.playing_changed, timeout=TIMEOUT_MS) as blocker:
        playback.toggle()
    assert blocker.args == [False]
