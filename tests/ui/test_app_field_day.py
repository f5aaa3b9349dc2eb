"""A field day with a camera not among the presets, as a biologist met it (issue 49): two
clips added with their SRTs, one camera typed once for both, a clip measured with suggested
widths that keep to the body at the flipper and tail stations, fitted, then an altitude
calibration imported from a table of another camera (refused until that camera is given, never
applied to these clips) and one of these clips' own camera (applied), after which the fit says
it is out of date; the Xcertainty export keeps the two clips' animals apart and dates them from
the SRTs."""

import csv
import shutil
from dataclasses import replace
from datetime import timedelta
from pathlib import Path

import numpy as np
import pytest
from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QAbstractSpinBox, QApplication

from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.io.srt import parse_srt, srt_clock_start
from dolphinfit.core.measure.annotation import place_stations, station_widths, suggest_edges
from dolphinfit.core.measure.mask_midline import midline_from_mask, suggested_edges
from dolphinfit.core.measure.stations import STATION_PCT
from dolphinfit.core.project.fit_settings import FitSettings
from dolphinfit.core.project.edits import offsets_from_edges
from dolphinfit.core.project.model import with_animal
from dolphinfit.core.synth.body_view import body_mask
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.sample import ensure_clip
from dolphinfit.ui.dialogs.calibration_dialog import NO_CAMERA, CalibrationDialog
from dolphinfit.ui.dialogs.camera_dialog import CameraDialog
from dolphinfit.ui.state.commands import edit_measurement, push_edit
from dolphinfit.ui.state.project_model import Change

from .test_app_calibration import MAVIC_AIR_2, MEDIDOR_CALIB, choose_camera

# a drone whose camera no preset describes (1-inch sensor, 10.3 mm lens)
SMALL = dict(width_px=480, height_px=270, fps=5.0, duration_s=2.0, altitude_m=9.0,
             heading_deg=10.0, sea_state=0.3, focal_mm=10.3, sensor_width_mm=13.2)
CONFIGS = {"DJI_0001": SynthConfig(seed=3, **SMALL), "DJI_0002": SynthConfig(seed=5, **SMALL)}
LAUNCH_HEIGHT_M = 1.5
MEASURED_FRAME = 5
QUICK_FIT = FitSettings(start_s=0.0, end_s=0.8, fps=5.0, quality="quick")
CAMERA_SPINS = ("focal_mm", "sensor_width_mm", "image_width_px", "image_height_px")
RETRY_MS = 20
TIMEOUT_MS = 60_000
# the altimeter of the drone these clips were filmed with reads low: true = 0.4 + 1.04 × recorded
TRUE_OFFSET_M, TRUE_SCALE, OBJECT_M = 0.4, 1.04, 2.0


@pytest.fixture(scope="module")
def clips_folder(tmp_path_factory) -> Path:
    """Two clips of two dolphins with their DJI SRTs, in a folder of their own."""
    renders = tmp_path_factory.mktemp("renders")
    folder = tmp_path_factory.mktemp("field_day") / "day1"
    folder.mkdir()
    for name, config in CONFIGS.items():
        files = ensure_clip(config, renders / name)
        shutil.copy(files.video, folder / f"{name}.mp4")
        shutil.copy(files.srt, folder / f"{name}.SRT")
    return folder


def answer_camera_dialog(values: tuple[float, float, int, int]) -> list[str]:
    """Answer the next camera dialog with ``values`` typed in; its title is kept."""
    titles = []

    def answer() -> None:
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, CameraDialog):
            QTimer.singleShot(RETRY_MS, answer)
            return
        titles.append(dialog.windowTitle())
        for name, value in zip(CAMERA_SPINS, values):
            dialog.findChild(QAbstractSpinBox, name).setValue(value)
        dialog.accept()

    QTimer.singleShot(0, answer)
    return titles


def own_calibration_table(path: Path, focal_px: float, camera: tuple) -> Path:
    """Our CSV layout: a 2 m object at five recorded altitudes, with the camera's columns."""
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(["image", "altitude_m", "pixel_length", "object_length_m", "focal_mm",
                         "sensor_width_mm", "image_width_px"])
        for recorded in (8.0, 10.0, 12.0, 15.0, 20.0):
            pixels = OBJECT_M * focal_px / (TRUE_OFFSET_M + TRUE_SCALE * recorded)
            writer.writerow([f"board_{recorded:g}m.jpg", recorded, f"{pixels:.3f}", OBJECT_M,
                             *camera[:3]])
    return path


def true_body_widths(midline: np.ndarray) -> np.ndarray:
    """(S,) px: the widths of the body without its fins (core.synth.body_view) at the
    stations of ``midline`` on the measured frame of DJI_0001."""
    body = body_mask(CONFIGS["DJI_0001"], MEASURED_FRAME)
    stations = place_stations(midline)
    return station_widths(stations, suggest_edges(body, stations))


def test_a_field_day_with_a_camera_not_among_the_presets(qtbot, make_window, clips_folder,
                                                         tmp_path):
    window = make_window((1600, 1000))
    window.ask.report = lambda title, text, details: None
    window.ask.launch_height = lambda names: LAUNCH_HEIGHT_M
    with qtbot.waitSignal(window.state.session_opened, timeout=TIMEOUT_MS):
        window.intake.add([clips_folder])
    model = window.model
    assert [clip.name for clip in model.project.clips] == ["DJI_0001.mp4", "DJI_0002.mp4"]

    # one camera, typed once, for both clips selected together; typed values are not
    # "approximate"; one step that Ctrl+Z undoes
    config = CONFIGS["DJI_0001"]
    typed = (config.focal_mm, config.sensor_width_mm, config.width_px, config.height_px)
    tree = window.project_panel.tree
    for row in (0, 1):
        tree.topLevelItem(row).setSelected(True)
    assert window.project_panel.selected_clips() == [0, 1]
    titles = answer_camera_dialog(typed)
    window.actions_by_name["camera"].trigger()
    qtbot.waitUntil(lambda: all(clip.camera.focal_mm == config.focal_mm
                                for clip in model.project.clips), timeout=TIMEOUT_MS)
    assert titles == ["Camera and video mode of 2 clips"]
    focal_px = config.focal_mm / config.sensor_width_mm * config.width_px
    for clip in model.project.clips:
        assert not clip.camera.approximate
        assert clip.camera.intrinsics().focal_px == pytest.approx(focal_px)   # 374.5 px
    model.undo_stack.undo()
    assert all(clip.camera.focal_mm != config.focal_mm for clip in model.project.clips)
    model.undo_stack.redo()
    assert all(clip.camera.focal_mm == config.focal_mm for clip in model.project.clips)

    # DJI_0001 measured: masks from a click, the length from the mask, the widths suggested
    model.select(0)
    qtbot.waitUntil(lambda: window.state.session_for(0) is not None, timeout=TIMEOUT_MS)
    with qtbot.waitSignal(window.state.frame_shown, timeout=TIMEOUT_MS):
        window.go_to_frame(MEASURED_FRAME)
    window.on_measure_frame()
    animal = model.project.clips[0].animals[0]
    push_edit(model, with_animal(model.project, 0, 0, replace(animal, fit_settings=QUICK_FIT)),
              "a quick fit", Change("structure"))
    truth_mask = read_masks(ensure_clip(config, tmp_path / "again").masks_dir)
    seed = np.argwhere(truth_mask.mask(MEASURED_FRAME)).mean(axis=0)[::-1]
    window.masks.arm_click_seed()
    window.canvas.image_clicked.emit(float(seed[0]), float(seed[1]), None)
    qtbot.waitUntil(lambda: model.project.clips[0].masks_path is not None, timeout=TIMEOUT_MS)
    project_dir = model.path.parent
    mask = read_masks(project_dir / model.project.clips[0].masks_path).mask(MEASURED_FRAME)
    midline = midline_from_mask(mask)
    edit_measurement(model, model.current_key(), replace(model.current_measurement(),
                                                         midline_px=midline), "length")
    assert "1 measured" in tree.topLevelItem(0).text(1)   # counted as soon as drawn
    window.on_suggest_edges()
    qtbot.waitUntil(lambda: np.isfinite(model.current_measurement().offsets_px).sum() > 30,
                    timeout=TIMEOUT_MS)
    assert window.actions_by_name["widths_mode"].isChecked()   # the edges drawn at once
    stations = place_stations(midline)
    offsets = model.current_measurement().offsets_px   # side A positive, side B negative
    suggested = offsets[:, 0] - offsets[:, 1]
    walked = station_widths(stations, suggest_edges(mask, stations))   # to the outline
    truth = true_body_widths(midline)
    widest = np.nanmax(truth)
    for pct in (30, 90, 95):   # the flipper station and the tail stock's, beside the flukes
        at = int(np.flatnonzero(STATION_PCT == pct)[0])
        assert suggested[at] == pytest.approx(truth[at], abs=1.5 + 0.1 * widest), pct
    assert walked[-1] > 2 * truth[-1]   # the outline at 95 % is the fluke lobes'

    # the fit, with masks for its frames
    qtbot.waitUntil(lambda: not window.masks.tracker.is_running, timeout=120_000)
    qtbot.waitUntil(lambda: window.fits.panel.start_button.isEnabled(), timeout=TIMEOUT_MS)
    with qtbot.waitSignal(window.fits.worker.finished, timeout=300_000):
        window.fits.panel.start_button.click()
    qtbot.waitUntil(lambda: "3D fit" in window.fits.panel.status.text(), timeout=TIMEOUT_MS)
    assert "out of date" not in window.fits.panel.status.text()

    # a calibration table of another camera: no line until its camera is given, then the
    # CLI's; these clips are of another camera and cannot take it
    def calibrate_from_medidor(current, clip_camera, clip_preset, clips, ticked):
        dialog = CalibrationDialog(current, clip_camera, clip_preset, clips, ticked, window)
        qtbot.addWidget(dialog)
        dialog.show()
        dialog.import_table(MEDIDOR_CALIB, "barometer")
        qtbot.waitUntil(lambda: NO_CAMERA in dialog.summary.text(), timeout=TIMEOUT_MS)
        assert dialog.calibration is None
        assert [box.isChecked() for box in dialog.clip_boxes.values()] == [False, False]
        choose_camera(qtbot, dialog, MAVIC_AIR_2)
        qtbot.waitUntil(lambda: dialog.calibration is not None, timeout=TIMEOUT_MS)
        assert dialog.calibration.slope == pytest.approx(1.6492, abs=1e-4)
        assert not any(box.isEnabled() for box in dialog.clip_boxes.values())
        dialog.reject()
        return None

    window.ask.altitude_calibration = calibrate_from_medidor
    window.actions_by_name["calibrate_altitude"].trigger()
    assert model.project.calibrations == ()

    # a table of these clips' own camera: its camera read from its columns, both clips ticked
    table = own_calibration_table(tmp_path / "board.csv", focal_px, typed)

    def calibrate_from_own_table(current, clip_camera, clip_preset, clips, ticked):
        dialog = CalibrationDialog(current, clip_camera, clip_preset, clips, ticked, window)
        qtbot.addWidget(dialog)
        dialog.show()
        dialog.import_table(table)
        qtbot.waitUntil(lambda: dialog.calibration is not None, timeout=TIMEOUT_MS)
        assert dialog.calibration.slope == pytest.approx(TRUE_SCALE, rel=1e-3)
        assert dialog.calibration.intercept_m == pytest.approx(TRUE_OFFSET_M, abs=0.01)
        dialog.name.setText("field drone barometer")
        for box in dialog.clip_boxes.values():
            assert box.isEnabled() and not box.isChecked()
            box.click()
        dialog.accept()
        return dialog.choice()

    window.ask.altitude_calibration = calibrate_from_own_table
    window.actions_by_name["calibrate_altitude"].trigger()
    assert [clip.altitude_calibration for clip in model.project.clips] == \
        ["field drone barometer"] * 2
    qtbot.waitUntil(lambda: window.fits.panel.status.text().startswith(
        "⚠ out of date: the clip's altitude calibration changed since this fit"),
        timeout=TIMEOUT_MS)

    # DJI_0002's dolphin measured by hand (its clicks where its outline is): "dolphin 1" too
    model.select(1)
    qtbot.waitUntil(lambda: window.state.session_for(1) is not None, timeout=TIMEOUT_MS)
    with qtbot.waitSignal(window.state.frame_shown, timeout=TIMEOUT_MS):
        window.go_to_frame(MEASURED_FRAME)
    window.on_measure_frame()
    outline = read_masks(ensure_clip(CONFIGS["DJI_0002"], tmp_path / "second").masks_dir).mask(
        MEASURED_FRAME)
    by_hand = midline_from_mask(outline)
    measurement = replace(model.current_measurement(), midline_px=by_hand)
    edit_measurement(model, model.current_key(), offsets_from_edges(
        measurement, suggested_edges(outline, place_stations(by_hand))), "by hand")
    assert model.project.clips[1].animals[0].animal_id == "dolphin 1"

    # the Xcertainty export: one whale_ID per animal of the project, the SRT's day
    out = tmp_path / "export"
    out.mkdir()
    window.ask.export_dir = lambda start: out
    window.exports.last_export = []
    window.actions_by_name["export_project"].trigger()
    qtbot.waitUntil(lambda: bool(window.exports.last_export), timeout=TIMEOUT_MS)
    (xcertainty,) = [Path(p) for p in window.exports.last_export if "xcertainty" in Path(p).name
                     and "calib" not in Path(p).name]
    with xcertainty.open(encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    recorded = srt_clock_start(parse_srt(clips_folder / "DJI_0001.SRT")) + timedelta(
        seconds=MEASURED_FRAME / config.fps)
    day = (str(recorded.year), str(recorded.timetuple().tm_yday))
    assert [(row["whale_ID"], row["year"], row["DOY"]) for row in rows] == [
        ("DJI_0001 dolphin 1", *day), ("DJI_0002 dolphin 1", *day)]
    assert (recorded.year, recorded.timetuple().tm_yday) == (2024, 153)
