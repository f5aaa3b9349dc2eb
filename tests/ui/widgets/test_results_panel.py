"""ResultsPanel and ResultsWorker: the numbers shown are core's, they follow edits and settings,
and the Monte Carlo runs off the GUI thread."""

import time
from dataclasses import replace

import numpy as np
import pytest
from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QLabel

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation import pixel_measurements, place_stations
from dolphinfit.core.measure.baseline import BaselineEstimate, BaselineSettings, estimate_baseline
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.records import default_error_model
from dolphinfit.core.project import edits
from dolphinfit.core.project.model import Animal, ClipEntry, Measurement, MeasurementKey, Project
from dolphinfit.core.project.results import measure_length
from dolphinfit.ui.state.commands import edit_measurement
from dolphinfit.ui.state.project_model import ProjectModel
from dolphinfit.ui.widgets.results_panel import ResultsPanel
from dolphinfit.ui.workers.results_worker import ResultsWorker

TIMEOUT_MS = 10_000
CAMERA = CameraPreset("test-4k", "", 8.8, 13.2, 3840, 2160, "test", False)
ALTITUDE_M, SOURCE = 18.0, "barometer"
KEY = MeasurementKey(0, 0, 0)


def _measurement(frame_idx: int, max_width_px: float) -> Measurement:
    """A straight 600 px dolphin with widths max_width_px·sin(π·fraction)."""
    midline = np.array([[1000.0, 800.0], [1480.0, 1160.0]])
    widths = max_width_px * np.sin(np.pi * place_stations(midline).fractions)
    return Measurement(frame_idx, midline, np.stack([widths / 2, -widths / 2], axis=1))


def _project() -> Project:
    animal = Animal("dolphin 1", measurements=(_measurement(5, 100.0), _measurement(9, 110.0),
                                               Measurement(12)))
    return Project(clips=(ClipEntry("DJI_0001.MP4", "video", CAMERA, animals=(animal,)),))


def _constant(clip_idx: int, frame_idx: int) -> tuple[float, str]:
    return ALTITUDE_M, SOURCE


def _core_estimate(project: Project, key: MeasurementKey, num_draws: int = 0
                   ) -> BaselineEstimate:
    """core's elliptical estimate of a measured frame, without the project and UI layers."""
    measurement = project.clips[key.clip].animals[key.animal].measurements[key.measurement]
    settings = BaselineSettings(hw=load_hw_preset(project.hw_ratios), tail=project.tail)
    return estimate_baseline(pixel_measurements(measurement.to_annotation()),
                             CAMERA.intrinsics().focal_px, ALTITUDE_M, settings,
                             default_error_model(SOURCE, CAMERA.approximate), num_draws,
                             np.random.default_rng(0))


@pytest.fixture
def make_panel(qtbot):
    """Builds panels on the test project (with a given worker); stops their threads after."""
    panels = []

    def make(worker: ResultsWorker | None = None) -> tuple[ProjectModel, ResultsPanel]:
        model = ProjectModel(_project())
        panel = ResultsPanel(model, worker)
        qtbot.addWidget(panel)
        panels.append(panel)
        return model, panel

    yield make
    for panel in panels:
        panel.shutdown()


@pytest.fixture
def setup(make_panel):
    return make_panel()


def _volume_shown(panel: ResultsPanel) -> float:
    return panel.current_result().record["volume_m3"]


def test_shows_core_values_then_the_interval(setup, qtbot):
    model, panel = setup
    with qtbot.waitSignal(panel.result_shown, timeout=TIMEOUT_MS):
        panel.set_altitude_lookup(_constant)
    expected = _core_estimate(model.project, KEY)
    assert _volume_shown(panel) == pytest.approx(float(expected.point.volume_m3), abs=1e-9)
    assert panel.values["volume_m3"].text() == f"{float(expected.point.volume_m3):.4f}"
    assert panel.values["gsd"].text() == f"{ALTITUDE_M / CAMERA.intrinsics().focal_px * 100:.3f}"
    assert panel.values["frame"].text() == "5"
    assert panel.intervals["volume_m3"].text() == "…"
    with qtbot.waitSignal(panel.worker.interval_ready, timeout=TIMEOUT_MS):
        pass
    mc = _core_estimate(model.project, KEY, num_draws=2000).interval
    assert panel.intervals["volume_m3"].text() == \
        f"{float(mc.volume_m3.low):.4f} – {float(mc.volume_m3.high):.4f}"
    assert panel.intervals["mass_kg"].text() == \
        f"{float(mc.mass_kg.low):.1f} – {float(mc.mass_kg.high):.1f}"
    assert panel.stations.item(9, 1).text() == f"{float(expected.point.widths_m[9]):.3f}"
    assert panel.stations.item(18, 2).text() == "from 85 %"
    assert "provisional" in panel.warnings.text()


def test_animal_summary_over_its_measurable_frames(setup, qtbot):
    model, panel = setup
    figures = []
    panel.animal_figures.connect(figures.append)
    with qtbot.waitSignal(panel.worker.animal_ready, timeout=TIMEOUT_MS) as blocker:
        panel.set_altitude_lookup(_constant)
    results, summary = blocker.args
    volumes = [float(_core_estimate(model.project, MeasurementKey(0, 0, m)).point.volume_m3)
               for m in (0, 1)]
    assert len(results) == 2 and summary.num_left_out == 1
    assert summary.spreads["volume_m3"].mean == pytest.approx(np.mean(volumes), rel=1e-12)
    assert panel.animal_cells["volume_m3", "mean"].text() == f"{np.mean(volumes):.4f}"
    assert panel.animal_title.text() == "dolphin 1: n = 2 frames; 1 not measurable yet"
    assert figures[-1][MeasurementKey(0, 0, 1)].endswith(f"{volumes[1]:.3f} m³")
    assert MeasurementKey(0, 0, 2) not in figures[-1]


def test_width_from_names_suggested_and_moved_edges(setup, qtbot):
    """Suggested, suggested-then-moved and clicked edges each say so; mixed sides say both."""
    model, panel = setup
    with qtbot.waitSignal(panel.result_shown, timeout=TIMEOUT_MS):
        panel.set_altitude_lookup(_constant)
    assert panel.stations.item(3, 2).text() == "measured"
    m = model.current_measurement()
    stations = edits.stations_of(m)
    edges = stations.points_px[:, None] + m.offsets_px[..., None] * stations.normals[:, None]
    m = edits.offsets_from_edges(m, edges, only_missing=False)
    m = edits.move_offset(edits.move_offset(m, 1, 0, m.offsets_px[1, 0] + 1.0), 1, 1,
                          m.offsets_px[1, 1] - 1.0)
    with qtbot.waitSignal(panel.result_shown, timeout=TIMEOUT_MS):
        edit_measurement(model, KEY, edits.set_offset(m, 2, 1, m.offsets_px[2, 1]), "edges")
    assert [panel.stations.item(row, 2).text() for row in range(4)] == [
        "suggested", "suggested, moved", "A suggested / B measured", "suggested"]


def test_editing_the_measurement_updates_the_volume(setup, qtbot):
    model, panel = setup
    with qtbot.waitSignal(panel.result_shown, timeout=TIMEOUT_MS):
        panel.set_altitude_lookup(_constant)
    before = _volume_shown(panel)
    wider = replace(_measurement(5, 100.0),
                    offsets_px=model.current_measurement().offsets_px * 1.2)
    edit_measurement(model, KEY, wider, "move handles")
    qtbot.waitUntil(lambda: _volume_shown(panel) != before, timeout=TIMEOUT_MS)
    expected = float(_core_estimate(model.project, KEY).point.volume_m3)
    assert _volume_shown(panel) == pytest.approx(expected, abs=1e-9)
    assert _volume_shown(panel) == pytest.approx(before * 1.2 ** 2, rel=1e-9)  # width × height


def test_a_drag_shows_nominal_values_and_one_interval_at_the_end(make_panel, qtbot):
    model, panel = make_panel(ResultsWorker(debounce_s=1.0))  # steps come far faster
    with qtbot.waitSignal(panel.worker.interval_ready, timeout=TIMEOUT_MS):
        panel.set_altitude_lookup(_constant)
    intervals = []
    panel.worker.interval_ready.connect(lambda request_id, result: intervals.append(result))
    measurement = model.current_measurement()
    for step in range(1, 31):  # one drag: 30 moves merged into one undo step
        moved = replace(measurement, offsets_px=measurement.offsets_px * (1 + step / 100))
        with qtbot.waitSignal(panel.result_shown, timeout=TIMEOUT_MS) as blocker:
            edit_measurement(model, KEY, moved, "drag", merge_tag=("drag", KEY))
        assert blocker.args[0].estimate.interval is None  # nominal, before any Monte Carlo
    qtbot.waitUntil(lambda: len(intervals) == 1, timeout=TIMEOUT_MS)
    panel.shutdown()  # nothing more can come
    assert len(intervals) == 1 and model.undo_stack.count() == 1
    assert _volume_shown(panel) == pytest.approx(
        float(_core_estimate(model.project, KEY).point.volume_m3), abs=1e-9)


def test_switching_the_hw_preset_is_one_undo_step(setup, qtbot):
    model, panel = setup
    with qtbot.waitSignal(panel.result_shown, timeout=TIMEOUT_MS):
        panel.set_altitude_lookup(_constant)
    before = _volume_shown(panel)
    panel.hw_combo.setCurrentText("circular")
    assert model.project.hw_ratios == "circular" and model.undo_stack.count() == 1
    qtbot.waitUntil(lambda: _volume_shown(panel) != before, timeout=TIMEOUT_MS)
    assert _volume_shown(panel) == pytest.approx(
        float(_core_estimate(model.project, KEY).point.volume_m3), abs=1e-9)
    model.undo_stack.undo()
    assert panel.hw_combo.currentText() == model.project.hw_ratios != "circular"
    qtbot.waitUntil(lambda: _volume_shown(panel) == before, timeout=TIMEOUT_MS)
    assert model.undo_stack.count() == 1  # syncing the combo pushed nothing


def test_missing_altitude_shows_its_message(setup, qtbot):
    _, panel = setup
    message = "DJI_0001.SRT: no valid altitude at frame 5"

    def no_altitude(clip_idx: int, frame_idx: int) -> tuple[float, str]:
        raise InputError(message)

    panel.set_altitude_lookup(no_altitude)
    assert panel.message.text() == message
    assert panel.current_result() is None and panel.values["volume_m3"].text() == "—"


def test_frame_without_length_says_why(setup, qtbot):
    model, panel = setup
    panel.set_altitude_lookup(_constant)
    with qtbot.waitSignal(panel.worker.failed, timeout=TIMEOUT_MS):
        model.select(0, 0, 2)
    assert panel.message.text().startswith("no body length yet")
    assert panel.current_result() is None


def test_a_length_without_widths_shows_the_length_and_its_interval(setup, qtbot):
    """Once the midline is drawn, before any width: the length (600 px × the GSD), then its
    interval; volume and mass wait for a width, and say so."""
    model, panel = setup
    panel.set_altitude_lookup(_constant)
    midline = model.project.clips[0].animals[0].measurements[0].midline_px
    with qtbot.waitSignal(panel.worker.nominal_ready, timeout=TIMEOUT_MS):
        model.select(0, 0, 2)
        edit_measurement(model, MeasurementKey(0, 0, 2), Measurement(12, midline), "length")
    length_m = 600 * ALTITUDE_M / CAMERA.intrinsics().focal_px
    assert panel.values["length_m"].text() == f"{length_m:.3f}"
    assert panel.values["frame"].text() == "12"
    assert panel.values["volume_m3"].text() == panel.values["mass_kg"].text() == "—"
    assert "once a width is placed" in panel.message.text()
    assert panel.current_result() is None
    with qtbot.waitSignal(panel.worker.interval_ready, timeout=TIMEOUT_MS):
        pass
    core = measure_length(model.project, MeasurementKey(0, 0, 2), ALTITUDE_M, SOURCE,
                          panel.worker.num_draws).interval
    assert panel.intervals["length_m"].text() == f"{core.low:.3f} – {core.high:.3f}"
    assert core.low < length_m < core.high


def test_event_loop_turns_during_a_long_monte_carlo(make_panel, qtbot):
    worker = ResultsWorker(num_draws=20_000)
    _, panel = make_panel(worker)
    ticks = []
    timer = QTimer(interval=10)
    timer.timeout.connect(lambda: ticks.append(time.perf_counter()))
    timer.start()
    start = time.perf_counter()
    with qtbot.waitSignal(worker.interval_ready, timeout=30_000):
        panel.set_altitude_lookup(_constant)
    elapsed_s = time.perf_counter() - start
    timer.stop()
    assert panel.current_result().estimate.interval.num_draws == 20_000
    assert elapsed_s > 0.3  # the debounce, then the Monte Carlo
    # at least an eighth of the 10 ms ticks, of the time it really took (a loaded machine
    # delays timers; a GUI thread blocked by the Monte Carlo gets none while it runs)
    assert len(ticks) >= max(10, elapsed_s / 0.010 / 8)


def _cut_off_labels(panel: ResultsPanel) -> None:
    """Fails naming the visible one-line labels narrower than their text."""
    cut = [label.text() for label in panel.findChildren(QLabel)
           if label.isVisible() and not label.wordWrap()
           and label.width() < label.sizeHint().width()]
    assert not cut


def test_nothing_is_cut_off_at_360_px(setup, qtbot):
    _, panel = setup
    panel.resize(360, 700)  # short enough for a vertical scroll bar
    panel.show()
    with qtbot.waitSignal(panel.worker.interval_ready, timeout=TIMEOUT_MS):
        panel.set_altitude_lookup(_constant)
    qtbot.waitUntil(lambda: panel.animal_cells["mass_kg", "range"].text() != "—",
                    timeout=TIMEOUT_MS)
    qtbot.waitUntil(lambda: _cut_off_labels(panel), timeout=TIMEOUT_MS)  # after the relayout
