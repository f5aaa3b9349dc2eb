"""Altitude calibration in the app: five images of a 4 m board measured by two clicks each,
the line fitted, the clip corrected, and the measured still's interval narrowing (the
barometer's 5 % altitude SD replaced by the calibration's, under 3 % from five shots)."""

from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
from PySide6.QtCore import QPointF

from dolphinfit.core.project.calibrations import clip_calibration
from dolphinfit.core.project.model import AltitudeSpec
from dolphinfit.ui.dialogs.calibration_dialog import CalibrationDialog

from .ellipse_scene import HEIGHT, LEFT, WIDTH
from .test_app import SIGNAL_TIMEOUT_MS, measure_by_hand, open_and_wait

BOARD_M = 4.0
RECORDED_M = (10.0, 15.0, 20.0, 25.0, 30.0)
TRUE_OFFSET_M, TRUE_SCALE = 0.5, 1.05   # the altimeter reads low
START_PX = np.array([150.0, 200.0])


def _board_images(folder: Path, focal_px: float) -> list[tuple[Path, float, float]]:
    """(image, recorded altitude, board length px): a white board on water at each altitude."""
    shots = []
    for recorded in RECORDED_M:
        length = BOARD_M * focal_px / (TRUE_OFFSET_M + TRUE_SCALE * recorded)
        image = np.full((HEIGHT, WIDTH, 3), (120, 90, 20), np.uint8)
        end = START_PX + [length, 0.0]
        cv2.line(image, tuple(START_PX.astype(int)), tuple(end.astype(int)), (255, 255, 255), 5)
        path = folder / f"board_{recorded:g}m.png"
        cv2.imwrite(str(path), image)
        shots.append((path, recorded, length))
    return shots


def _interval_share(window) -> float:
    record = window.results.current_result().record
    interval = record["uncertainty"]["volume_m3"]
    return (interval["high"] - interval["low"]) / record["volume_m3"]


def test_calibrate_the_altimeter_from_five_board_images(qtbot, new_window, still, tmp_path):
    window = new_window()
    window.ask.altitude = lambda *asked: AltitudeSpec(constant_m=20.0, source="barometer")
    open_and_wait(qtbot, window, still)
    measure_by_hand(qtbot, window)
    qtbot.waitUntil(lambda: window.results.current_result() is not None
                    and window.results.current_result().estimate.interval is not None,
                    timeout=SIGNAL_TIMEOUT_MS)
    before = window.results.current_result().record
    share_before = _interval_share(window)
    camera = window.model.project.clips[0].camera
    shots = _board_images(tmp_path, camera.intrinsics().focal_px)

    def calibrate(camera, current, clips, ticked):
        dialog = CalibrationDialog(camera, current, clips, ticked, window)
        qtbot.addWidget(dialog)
        dialog.show()
        qtbot.waitExposed(dialog)
        dialog.name.setText("test drone barometer")
        dialog.object_length.setValue(BOARD_M)
        for row, (path, recorded, length) in enumerate(shots):
            dialog.add_images([path])
            qtbot.waitUntil(lambda: dialog.table.rowCount() == row + 1, timeout=SIGNAL_TIMEOUT_MS)
            qtbot.waitUntil(lambda: dialog.canvas.image_rect().width() > 0,
                            timeout=SIGNAL_TIMEOUT_MS)
            for end in (START_PX, START_PX + [length, 0.0]):
                qtbot.mouseClick(dialog.canvas.viewport(), LEFT,
                                 pos=dialog.canvas.mapFromScene(QPointF(*end)))
            dialog.set_altitude(row, recorded)
        qtbot.waitUntil(lambda: dialog.calibration is not None
                        and dialog.calibration.num_shots == 5, timeout=SIGNAL_TIMEOUT_MS)
        assert dialog.calibration.slope == pytest.approx(TRUE_SCALE, abs=0.03)
        assert "spread" in dialog.summary.text()
        assert list(dialog.clip_boxes) == [0] and dialog.clip_boxes[0].isChecked()
        dialog.accept()
        assert dialog.result() == CalibrationDialog.DialogCode.Accepted
        return dialog.choice()

    window.ask.altitude_calibration = calibrate
    window.actions_by_name["calibrate_altitude"].trigger()
    assert window.model.project.clips[0].altitude_calibration == "test drone barometer"
    qtbot.waitUntil(lambda: "recorded_altitude_m" in window.results.current_result().record
                    and window.results.current_result().estimate.interval is not None,
                    timeout=SIGNAL_TIMEOUT_MS)
    after = window.results.current_result().record
    assert after["altitude_m"] == pytest.approx(TRUE_OFFSET_M + TRUE_SCALE * 20.0, rel=0.02)
    assert after["length_m"] / before["length_m"] == pytest.approx(after["altitude_m"] / 20.0)
    errors = after["uncertainty"]["errors"]
    calibration = clip_calibration(window.model.project, 0)
    assert errors["altitude_sd_fraction"] == pytest.approx(calibration.altitude_sd_fraction(20.0))
    assert errors["altitude_sd_fraction"] < 0.03 < 0.05 == before["uncertainty"]["errors"][
        "altitude_sd_fraction"]                             # the barometer's default
    assert _interval_share(window) < 0.75 * share_before
    # the status bar shows the altitude the results measure with, and the one recorded
    status = window.status_label.text()
    assert (f"altitude {after['altitude_m']:.2f} m (calibrated by 'test drone barometer'; "
            "20.00 m constant") in status
    window.model.undo_stack.undo()
    assert window.model.project.calibrations == ()
    assert "altitude 20.00 m (constant" in window.status_label.text()


def test_frames_of_a_clip_come_with_their_srt_altitudes(qtbot, tmp_path):
    """Every 25th frame of the sample video becomes a shot at the altitude its SRT records
    there plus the launch height asked for (the SRT records height above the take-off point);
    a frame is read when its shot is selected, measured by two clicks, and only measured shots
    count. Cancelling the launch height adds nothing."""
    import shutil

    from dolphinfit.core.camera_presets import get_preset
    from dolphinfit.core.io.telemetry import load_telemetry
    from dolphinfit.core.io.video import open_clip
    from dolphinfit.core.project.sample import ensure_sample_project

    sample = ensure_sample_project().parent
    video = tmp_path / "clip.mp4"
    for name in ("clip.mp4", "clip.SRT"):
        shutil.copy(sample / name, tmp_path / name)
    clip = open_clip(video)
    camera = replace(get_preset("dji-mavic3-fhd"), image_width_px=clip.width_px,
                     image_height_px=clip.height_px)
    dialog = CalibrationDialog(camera, None, [], set())
    qtbot.addWidget(dialog)
    dialog.show()
    qtbot.waitExposed(dialog)
    asked = []
    dialog.ask_launch_height = lambda path: asked.append(path.name)   # cancelled
    dialog.add_clip_frames(video, every=25)
    qtbot.waitUntil(lambda: asked == ["clip.mp4"], timeout=SIGNAL_TIMEOUT_MS)
    assert dialog.table.rowCount() == 0
    dialog.ask_launch_height = lambda path: 1.5
    dialog.add_clip_frames(video, every=25)
    qtbot.waitUntil(lambda: dialog.table.rowCount() == 2, timeout=SIGNAL_TIMEOUT_MS)
    altitudes = load_telemetry(clip).altitude_m + 1.5
    assert [dialog.table.item(row, 1).text() for row in range(2)] == \
        [f"{altitudes[0]:g}", f"{altitudes[25]:g}"]
    assert dialog.table.item(0, 0).text() == "clip.mp4#frame=0"
    assert dialog.calibration_set().shots == ()          # nothing measured yet
    qtbot.waitUntil(lambda: dialog.canvas.image_rect().width() > 0, timeout=SIGNAL_TIMEOUT_MS)
    for end in ((400.0, 300.0), (700.0, 300.0)):
        qtbot.mouseClick(dialog.canvas.viewport(), LEFT,
                         pos=dialog.canvas.mapFromScene(QPointF(*end)))
    (shot,) = dialog.calibration_set().shots
    assert shot.image.endswith("#frame=0") and shot.pixel_length == pytest.approx(300, abs=2)
