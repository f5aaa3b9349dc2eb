"""The whole app driven as a user would: open media, measure with mouse and keys, undo, save,
reopen, restore after a crash, relink moved media, export, and stay responsive.

Measuring happens on a still image of the ellipse scene (ellipse_scene.py), whose outline is
known; frame stepping on the bundled sample project (a video with a DJI SRT).
"""

import csv
import json
import shutil
import threading
import time
from pathlib import Path

import cv2
import numpy as np
import pytest
from PySide6.QtCore import QPoint, QPointF, Qt, QTimer

from dolphinfit.core.measure.morphometrix import read_morphometrix
from dolphinfit.core.measure.annotation import pixel_measurements, place_stations
from dolphinfit.core.measure.baseline import BaselineSettings, estimate_baseline
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.uncertainty import ErrorModel
from dolphinfit.core.project.model import AltitudeSpec
from dolphinfit.core.project.project_file import autosave_path, find_moved_media
from dolphinfit.core.project.sample import ensure_sample_project
from dolphinfit.ui.workers import results_worker
from dolphinfit.ui.main_window import MainWindow

from .app_waits import results_caught_up
from .ellipse_scene import LEFT, MIDLINE, analytic_widths, chord, dolphin_frame

ALTITUDE_M = 20.0   # the still's, as conftest.new_window answers it
CTRL = Qt.KeyboardModifier.ControlModifier
SHIFT = Qt.KeyboardModifier.ShiftModifier
SIGNAL_TIMEOUT_MS = 20_000


def open_and_wait(qtbot, window: MainWindow, path: Path) -> None:
    with qtbot.waitSignal(window.state.session_opened, timeout=SIGNAL_TIMEOUT_MS):
        window.files.open_path(path)
    qtbot.waitUntil(lambda: window.canvas.image_rect().width() > 0, timeout=SIGNAL_TIMEOUT_MS)


def press(qtbot, window: MainWindow, key: Qt.Key,
          modifier: Qt.KeyboardModifier = Qt.KeyboardModifier.NoModifier) -> None:
    window.canvas.setFocus()
    qtbot.keyClick(window.canvas, key, modifier)


def click(qtbot, window: MainWindow, uv: np.ndarray) -> None:
    pos: QPoint = window.canvas.mapFromScene(QPointF(*uv))
    qtbot.mouseClick(window.canvas.viewport(), LEFT, pos=pos)


def shown_volume(qtbot, window: MainWindow) -> float:
    """The volume the results panel shows once it has caught up with the current pixels
    (Monte Carlo interval included)."""
    qtbot.waitUntil(lambda: results_caught_up(window), timeout=SIGNAL_TIMEOUT_MS)
    return window.results.current_result().record["volume_m3"]


def engine_volume(window: MainWindow) -> float:
    """core's own estimate on the pixels the app holds."""
    clip = window.model.project.clips[window.model.clip_idx]
    pixels = pixel_measurements(window.model.current_measurement().to_annotation())
    estimate = estimate_baseline(pixels, clip.camera.intrinsics().focal_px, ALTITUDE_M,
                                 BaselineSettings(hw=load_hw_preset()),
                                 ErrorModel.default("laser", True), 0, np.random.default_rng(0))
    return float(estimate.point.volume_m3)


def measure_by_hand(qtbot, window: MainWindow) -> None:
    """Ctrl+M, three length clicks, then the 38 edges clicked in Tab order."""
    press(qtbot, window, Qt.Key.Key_M, CTRL)
    assert window.model.current_measurement() is not None
    for point in MIDLINE:
        click(qtbot, window, point)
    press(qtbot, window, Qt.Key.Key_W)
    assert window.overlay.mode == "widths"
    stations = place_stations(window.model.current_measurement().midline_px)
    for point, normal in zip(stations.points_px, stations.normals):
        for offset in chord(point, normal):
            click(qtbot, window, point + offset * normal)


@pytest.fixture
def measured(qtbot, new_window, still) -> MainWindow:
    """A window on the still (its altitude asked on opening), measured by hand and saved."""
    window = new_window()
    open_and_wait(qtbot, window, still)
    measure_by_hand(qtbot, window)
    press(qtbot, window, Qt.Key.Key_S, CTRL)
    return window


def test_measure_a_still_by_hand_and_read_the_engines_volume(qtbot, measured):
    window = measured
    assert window.model.project.clips[0].altitude == AltitudeSpec(constant_m=ALTITUDE_M,
                                                                  source="laser")
    m = window.model.current_measurement()
    assert m.is_station_done().all()
    widths = pixel_measurements(m.to_annotation()).widths_px
    # each click lands on a screen pixel: an edge is off by ≤ ½ screen px, a width by ≤ 1
    np.testing.assert_allclose(widths, analytic_widths(m.midline_px),
                               atol=1.0 / window.canvas.view_scale() + 1e-9)
    assert shown_volume(qtbot, window) == pytest.approx(engine_volume(window), rel=1e-12)
    panel = window.results.current_result()
    assert panel.estimate.interval.volume_m3.low < panel.record["volume_m3"] \
        < panel.estimate.interval.volume_m3.high
    assert "altitude 20.00 m (constant, laser" in window.status_label.text()
    assert "GSD" in window.status_label.text()

    # Tab to the first handle, nudge it out 1 px with the Up key, then undo and redo
    press(qtbot, window, Qt.Key.Key_Tab)
    station, side = window.overlay.selected_edge
    before = window.model.current_measurement().offsets_px[station, side]
    press(qtbot, window, Qt.Key.Key_Up)
    after = window.model.current_measurement().offsets_px[station, side]
    assert abs(after) - abs(before) == pytest.approx(1.0)
    press(qtbot, window, Qt.Key.Key_Z, CTRL)
    assert window.model.current_measurement().offsets_px[station, side] == before
    press(qtbot, window, Qt.Key.Key_Z, CTRL | SHIFT)
    assert window.model.current_measurement().offsets_px[station, side] == after

    # mirror side A doubles side A; skip leaves a station to interpolation, with a warning
    window.actions_by_name["mirror_a"].trigger()
    m = window.model.current_measurement()
    assert pixel_measurements(m.to_annotation()).widths_px[9] == pytest.approx(
        2 * m.offsets_px[9, 0])
    window.actions_by_name["mirror_none"].trigger()
    while window.overlay.selected_edge != (9, 0):  # Tab on to the 50 % station, side A
        press(qtbot, window, Qt.Key.Key_Tab)
    press(qtbot, window, Qt.Key.Key_S)
    assert window.model.current_measurement().skipped.sum() == 1
    shown_volume(qtbot, window)
    warnings = " ".join(window.results.current_result().estimate.warnings())
    assert "filled by linear interpolation" in warnings
    for _ in range(5):
        press(qtbot, window, Qt.Key.Key_Z, CTRL)
    assert not window.model.current_measurement().skipped.any()


def test_save_close_reopen_finds_everything(qtbot, new_window, still, measured):
    window = measured
    volume = shown_volume(qtbot, window)
    path = window.model.path
    assert path == still.with_suffix(".dolphinfit") and path.exists()
    assert not window.model.is_dirty and not autosave_path(path).exists()
    saved = window.model.current_measurement()
    window.close()

    again = new_window()
    open_and_wait(qtbot, again, path)
    m = again.model.current_measurement()
    np.testing.assert_array_equal(m.midline_px, saved.midline_px)
    np.testing.assert_array_equal(m.offsets_px, saved.offsets_px)
    assert shown_volume(qtbot, again) == pytest.approx(volume, rel=1e-12)
    assert not again.model.is_dirty


def test_unsaved_work_comes_back_after_a_crash(qtbot, new_window, still):
    window = new_window()
    open_and_wait(qtbot, window, still)
    press(qtbot, window, Qt.Key.Key_S, CTRL)
    measure_by_hand(qtbot, window)
    with qtbot.waitSignal(window.model.autosaved, timeout=SIGNAL_TIMEOUT_MS):
        pass  # written a moment after the last edit, without any save
    crashed = window.model.current_measurement()
    # the first window never closes (a crash); a new one opens the same project
    again = new_window()
    asked = []
    again.ask.restore_autosave = lambda path: asked.append(path) or True
    open_and_wait(qtbot, again, window.model.path)
    assert asked == [window.model.path]
    m = again.model.current_measurement()
    np.testing.assert_array_equal(m.offsets_px, crashed.offsets_px)
    assert again.model.is_dirty  # restored, not yet saved
    press(qtbot, again, Qt.Key.Key_Z, CTRL)  # the restore is one undo step
    assert again.model.current_measurement() is None


def test_media_changed_on_disk_is_asked_about_and_kept_until_the_user_agrees(qtbot, new_window,
                                                                           still):
    """The still replaced by another picture under its name: opening the project says so;
    declined, nothing changes (asked again next time); accepted, the clip takes the file as
    it is now in one undoable step."""
    import cv2

    window = new_window()
    open_and_wait(qtbot, window, still)
    press(qtbot, window, Qt.Key.Key_S, CTRL)
    path, before = window.model.path, window.model.project.clips[0].media_fingerprint
    assert before is not None
    cv2.imwrite(str(still), 255 - cv2.imread(str(still)))
    for agree in (False, True):
        again = new_window()
        asked = []
        again.ask.media_changed = lambda names, agree=agree: asked.append(names) or agree
        open_and_wait(qtbot, again, path)
        qtbot.waitUntil(lambda: asked == [[still.name]], timeout=SIGNAL_TIMEOUT_MS)
        qtbot.waitUntil(lambda: again.model.is_dirty == agree, timeout=SIGNAL_TIMEOUT_MS)
        after = again.model.project.clips[0].media_fingerprint
        assert (after != before) == agree
    press(qtbot, again, Qt.Key.Key_Z, CTRL)
    assert again.model.project.clips[0].media_fingerprint == before


def test_a_broken_project_file_is_named_and_left_as_it_was(qtbot, new_window, tmp_path):
    path = tmp_path / "cut.dolphinfit"
    path.write_text('{"schema_version": 1, "settings": {"hw_ra')   # cut short by a full disk
    window = new_window()
    errors = []
    window.ask.warn = lambda title, text: errors.append(text)   # the dialog the user reads
    window.files.open_path(path)
    assert len(errors) == 1 and "cut.dolphinfit: not valid JSON" in errors[0]
    assert "nothing was changed" in errors[0]
    assert path.read_text() == '{"schema_version": 1, "settings": {"hw_ra'
    assert window.model.path != path


@pytest.mark.qt_no_exception_capture   # the app's own handler must see the exception
def test_an_exception_in_a_slot_writes_a_crash_report_and_keeps_the_work(qtbot, new_window,
                                                                          still):
    """A slot that raises: the crash report names the last actions and holds the traceback,
    the unsaved measurement is in the autosave, and the user is told both; the app goes on."""
    from dolphinfit.core.crash_report import log_dir
    from dolphinfit.core.project.project_file import read_project
    from dolphinfit.ui.crash_handler import CrashHandler

    window = new_window()
    open_and_wait(qtbot, window, still)
    press(qtbot, window, Qt.Key.Key_S, CTRL)
    press(qtbot, window, Qt.Key.Key_M, CTRL)   # measure this frame: unsaved work
    assert window.model.is_dirty and not autosave_path(window.model.path).exists()
    told = []
    handler = CrashHandler(window.model, window.recent_actions,
                           lambda report, work: told.append((report, work)))
    handler.install()
    try:
        def broken_slot():
            raise ValueError("a station with no width")

        QTimer.singleShot(0, broken_slot)
        qtbot.waitUntil(lambda: bool(told), timeout=SIGNAL_TIMEOUT_MS)
    finally:
        handler.uninstall()
    ((report, work),) = told
    assert report.parent == log_dir()
    text = report.read_text()
    assert "ValueError: a station with no width" in text and "in broken_slot" in text
    assert "  save\n  measure_frame\n" in text
    kept = autosave_path(window.model.path)
    assert str(kept) in work
    frames = [[m.frame_idx for m in animal.measurements]
              for animal in read_project(kept).clips[0].animals]
    assert frames == [[0]] == [[m.frame_idx for m in animal.measurements]
                               for animal in window.model.project.clips[0].animals]
    press(qtbot, window, Qt.Key.Key_Z, CTRL)   # the app goes on
    assert window.model.current_measurement() is None


def test_moved_media_is_found_and_relinked(qtbot, new_window, still):
    window = new_window()
    open_and_wait(qtbot, window, still)
    press(qtbot, window, Qt.Key.Key_S, CTRL)
    path = window.model.path
    window.close()
    moved = still.parent / "2024-06-01" / still.name
    moved.parent.mkdir()
    shutil.move(still, moved)

    again = new_window()
    offered = []

    def relink(stored: str, project_dir: Path) -> Path:
        offered.extend(find_moved_media(project_dir, Path(stored).name))
        return offered[0]

    again.ask.relink = relink
    open_and_wait(qtbot, again, path)
    assert offered == [moved]
    assert again.model.project.clips[0].media_path == "2024-06-01/DJI_0001.png"
    assert again.model.is_dirty


def test_exports_of_the_project_read_back(qtbot, measured, tmp_path):
    window = measured
    volume = shown_volume(qtbot, window)
    out = tmp_path / "exports"
    window.ask.export_dir = lambda start: out
    with qtbot.waitSignal(window.exports.worker.finished, timeout=60_000):
        window.actions_by_name["export_project"].trigger()
    stem = "DJI_0001"
    with open(out / f"{stem}_wide.csv", newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 1
    length_px = pixel_measurements(window.model.current_measurement().to_annotation()).length_px
    assert float(rows[0]["TL_px"]) == pytest.approx(length_px, rel=1e-6)
    record = read_morphometrix(out / f"{stem}_mmx" / f"{stem}.csv")
    assert record.lengths_px["TL"] == pytest.approx(length_px, rel=1e-6)
    assert record.altitude_m == ALTITUDE_M
    results = json.loads((out / f"{stem}_results.json").read_text())
    assert results["frames"][stem]["result"]["volume_m3"] == pytest.approx(volume, rel=1e-12)
    assert results["animals"][0]["frames"] == [stem]
    receipt = cv2.imread(str(out / f"{stem}_receipts" / f"{stem}.png"))
    assert receipt.shape[:2] == dolphin_frame().shape[:2]
    assert set(window.exports.last_export) == {p for p in out.rglob("*") if p.is_file()}


def test_sample_project_frames_step_with_keys(qtbot, new_window):
    window = new_window()
    open_and_wait(qtbot, window, ensure_sample_project())
    last = window.state.session.source.clip.num_frames - 1
    for key, modifier, expected in ((Qt.Key.Key_Right, None, 1), (Qt.Key.Key_Right, SHIFT, 11),
                                    (Qt.Key.Key_Left, None, 10), (Qt.Key.Key_Right, CTRL, last),
                                    (Qt.Key.Key_Home, None, 0), (Qt.Key.Key_End, None, last)):
        with qtbot.waitSignal(window.state.frame_shown, timeout=SIGNAL_TIMEOUT_MS,
                              check_params_cb=lambda idx, e=expected: idx == e):
            press(qtbot, window, key, modifier or Qt.KeyboardModifier.NoModifier)
    assert f"frame {last} of 0–{last}" in window.status_label.text()
    assert "altitude 1" in window.status_label.text() and "cm/px" in window.status_label.text()
    press(qtbot, window, Qt.Key.Key_Home)
    with qtbot.waitSignal(window.playback.playing_changed, timeout=SIGNAL_TIMEOUT_MS):
        press(qtbot, window, Qt.Key.Key_Space)
    qtbot.waitUntil(lambda: window.state.frame_idx >= 3, timeout=SIGNAL_TIMEOUT_MS)
    press(qtbot, window, Qt.Key.Key_Space)
    assert not window.playback.is_playing


def test_the_gui_keeps_turning_while_a_slow_result_is_computed(qtbot, measured, monkeypatch):
    window = measured
    shown_volume(qtbot, window)
    started, release = threading.Event(), threading.Event()
    real = results_worker.measure_frame
    threads = []

    def slow(*args, **kwargs):
        threads.append(threading.current_thread())
        started.set()
        release.wait(10)
        return real(*args, **kwargs)

    monkeypatch.setattr(results_worker, "measure_frame", slow)
    ticks = []
    timer = QTimer(interval=20)
    timer.timeout.connect(lambda: ticks.append(time.monotonic()))
    timer.start()
    press(qtbot, window, Qt.Key.Key_Up)          # an edit: a new (slow) result request
    qtbot.waitUntil(started.is_set, timeout=SIGNAL_TIMEOUT_MS)
    begin = time.monotonic()
    qtbot.wait(600)
    press(qtbot, window, Qt.Key.Key_Up)          # the user keeps editing meanwhile
    qtbot.wait(400)
    ended = time.monotonic()
    release.set()
    timer.stop()
    assert threading.main_thread() not in threads   # the slow result is the worker's
    during = [t for t in ticks if begin <= t <= ended]
    # the 20 ms ticks went on while the worker was stuck: a quarter of them at least (idle:
    # nearly all), counted over the time the waits really took on a loaded machine
    assert len(during) >= 0.25 * (ended - begin) / 0.020
    assert window.model.undo_stack.count() >= 2


def test_the_window_opens_at_the_size_and_dock_layout_it_was_closed_with(qtbot, make_window):
    from dolphinfit.ui.main_window import MainWindow

    first = make_window(size=(1100, 800))  # within the test screen (restored sizes fit it)
    first.docks["Project"].hide()
    size = first.size()
    first.close()
    again = MainWindow()
    qtbot.addWidget(again)
    assert again.layout_restored and again.size() == size
    assert again.docks["Project"].isHidden() and not again.docks["Results"].isHidden()
    fresh = MainWindow(restore_layout=False)  # the README's screenshots start from defaults
    qtbot.addWidget(fresh)
    assert not fresh.layout_restored and not fresh.docks["Project"].isHidden()
    again.shutdown()
    fresh.shutdown()
