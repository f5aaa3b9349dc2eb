"""Altitude calibration in the app: five images of a 4 m board measured by two clicks each,
the line fitted, the clip corrected, and the measured still's interval narrowing (the
barometer's 5 % altitude SD replaced by the calibration's, under 3 % from five shots); a
MedidoR table fitted with the table's camera, never the open clip's."""

import json
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
from PySide6.QtCore import QPointF, QTimer
from PySide6.QtWidgets import QAbstractSpinBox, QApplication, QPushButton

from dolphinfit.app.cli import main
from dolphinfit.core.project.calibrations import clip_calibration
from dolphinfit.core.project.model import AltitudeSpec
from dolphinfit.ui.dialogs.calibration_dialog import NO_CAMERA, CalibrationDialog
from dolphinfit.ui.dialogs.camera_dialog import CameraDialog

from .ellipse_scene import HEIGHT, LEFT, WIDTH
from .test_app import SIGNAL_TIMEOUT_MS, measure_by_hand, open_and_wait

BOARD_M = 4.0
RECORDED_M = (10.0, 15.0, 20.0, 25.0, 30.0)
TRUE_OFFSET_M, TRUE_SCALE = 0.5, 1.05   # the altimeter reads low
START_PX = np.array([150.0, 200.0])
MEDIDOR_CALIB = Path(__file__).resolve().parents[1] / "data" / "real" / "medidor" / "calib.xlsx"
# the Mavic Air 2 at 2.7k, as MedidoR's GUI test enters it (tests/data/real/medidor/test-app-*.R)
MAVIC_AIR_2 = (7.6, 6.4, 2688, 1512)   # focal mm, sensor width mm, image width, height px
CAMERA_SPINS = ("focal_mm", "sensor_width_mm", "image_width_px", "image_height_px")
RETRY_MS = 20


def choose_camera(qtbot, dialog: CalibrationDialog,
                  values: tuple[float, float, int, int] | None = None) -> None:
    """Click Camera… and answer the camera dialog it opens: ``values`` typed in, or what it
    offers accepted."""
    def answer() -> None:
        camera_dialog = QApplication.activeModalWidget()
        if not isinstance(camera_dialog, CameraDialog):
            QTimer.singleShot(RETRY_MS, answer)
            return
        for name, value in zip(CAMERA_SPINS, values or ()):
            camera_dialog.findChild(QAbstractSpinBox, name).setValue(value)
        camera_dialog.accept()

    QTimer.singleShot(0, answer)
    qtbot.mouseClick(dialog.findChild(QPushButton, "choose_camera"), LEFT)


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

    def calibrate(current, clip_camera, clip_preset, clips, ticked):
        dialog = CalibrationDialog(current, clip_camera, clip_preset, clips, ticked, window)
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
        # no camera is assumed: the images' is chosen (the open clip's, offered first)
        assert dialog.calibration is None and NO_CAMERA in dialog.summary.text()
        assert list(dialog.clip_boxes) == [0] and not dialog.clip_boxes[0].isEnabled()
        choose_camera(qtbot, dialog)
        assert f"{WIDTH} px wide (chosen with Camera…)" in dialog.camera.text()
        qtbot.waitUntil(lambda: dialog.calibration is not None
                        and dialog.calibration.num_shots == 5, timeout=SIGNAL_TIMEOUT_MS)
        assert dialog.calibration.slope == pytest.approx(TRUE_SCALE, abs=0.03)
        assert "spread" in dialog.summary.text()
        assert dialog.clip_boxes[0].isEnabled() and not dialog.clip_boxes[0].isChecked()
        dialog.clip_boxes[0].click()
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
    dialog = CalibrationDialog(None, camera, None, [], set())
    qtbot.addWidget(dialog)
    dialog.show()
    qtbot.waitExposed(dialog)
    choose_camera(qtbot, dialog)
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


def test_a_medidor_table_is_fitted_with_its_own_camera_not_the_open_clips(qtbot, new_window,
                                                                        tmp_path):
    """MedidoR's calib.xlsx (351 shots of a 2.02 m object by a Mavic Air 2 at 2.7k, no camera
    columns) imported with a 1920 px clip open: no line until the camera is given, then the
    line `dolphinfit calibrate altitude` fits with that camera (scale 1.6492, offset
    −0.468 m), the object's length the table's; the clip, of another camera, is not ticked
    and cannot be."""
    still = tmp_path / "survey" / "DJI_0002.png"
    still.parent.mkdir()
    cv2.imwrite(str(still), np.full((1080, 1920, 3), 90, np.uint8))
    out = tmp_path / "cli.json"
    assert main(["calibrate", "altitude", str(MEDIDOR_CALIB), "--out", str(out),
                 "--focal-mm", "7.6", "--sensor-width-mm", "6.4", "--image-width", "2688"]) == 0
    cli = json.loads(out.read_text(encoding="utf-8"))
    window = new_window()
    open_and_wait(qtbot, window, still)
    assert window.model.project.clips[0].camera.image_width_px == 1920

    def calibrate(current, clip_camera, clip_preset, clips, ticked):
        dialog = CalibrationDialog(current, clip_camera, clip_preset, clips, ticked, window)
        qtbot.addWidget(dialog)
        dialog.show()
        qtbot.waitExposed(dialog)
        dialog.import_table(MEDIDOR_CALIB, "barometer")
        qtbot.waitUntil(lambda: dialog.table.rowCount() == 351, timeout=SIGNAL_TIMEOUT_MS)
        qtbot.waitUntil(lambda: NO_CAMERA in dialog.summary.text(), timeout=SIGNAL_TIMEOUT_MS)
        assert dialog.calibration is None and not dialog.figure.axes   # no line drawn
        assert dialog.camera.text().startswith("none") and "does not say its camera" in \
            dialog.status.text()
        assert dialog.object_length.value() == pytest.approx(2.02)
        dialog.name.setText("Mavic Air 2 barometer")
        dialog.accept()
        assert dialog.result() != CalibrationDialog.DialogCode.Accepted
        assert dialog.status.text() == f"No line yet: {NO_CAMERA}"

        choose_camera(qtbot, dialog, MAVIC_AIR_2)
        qtbot.waitUntil(lambda: dialog.calibration is not None, timeout=SIGNAL_TIMEOUT_MS)
        fitted = dialog.calibration
        assert "focal 7.6 mm, sensor 6.4 mm, 2688 px wide" in dialog.camera.text()
        assert (fitted.num_shots, fitted.object_length_m) == (cli["num_shots"], 2.02) == \
            (351, 2.02)
        for name in ("slope", "intercept_m", "residual_sd_fraction"):
            assert getattr(fitted, name) == pytest.approx(cli[name], rel=1e-9)
        assert fitted.slope == pytest.approx(1.6492, abs=1e-4)
        assert fitted.intercept_m == pytest.approx(-0.468, abs=1e-3)
        assert "true altitude = -0.47 m + 1.6492 × recorded" in dialog.summary.text()
        assert dialog.figure.axes
        assert not dialog.clip_boxes[0].isChecked() and not dialog.clip_boxes[0].isEnabled()
        dialog.accept()
        assert dialog.result() == CalibrationDialog.DialogCode.Accepted
        return dialog.choice()

    window.ask.altitude_calibration = calibrate
    window.actions_by_name["calibrate_altitude"].trigger()
    (calibration,) = window.model.project.calibrations
    assert (calibration.camera.focal_mm, calibration.camera.image_width_px) == (7.6, 2688)
    assert window.model.project.clips[0].altitude_calibration is None


def test_a_table_names_its_camera_by_a_preset_or_its_columns(qtbot, tmp_path):
    """With a preset of the Mavic Air 2 at 2.7k, calib.xlsx (Drone "Mavic Air 2", Resolution
    "2.7k") takes that camera by itself and gives the CLI's scale 1.6492; only the clip of
    that camera can be ticked, and none is. A second table whose columns state another
    camera is refused."""
    import pandas as pd

    from dolphinfit.core.camera_presets import CameraPreset, get_preset, save_user_preset

    air2 = CameraPreset("dji-mavic-air2-2.7k", "DJI Mavic Air 2, 1/2-inch CMOS, 2.7K video",
                        *MAVIC_AIR_2, "test", False)
    save_user_preset(air2)
    fhd = get_preset("dji-mavic3-fhd")
    clips = [(0, "mavic3.mp4", fhd.intrinsics().focal_px),
             (1, "air2.mp4", air2.intrinsics().focal_px)]
    dialog = CalibrationDialog(None, fhd, fhd.name, clips, set())
    qtbot.addWidget(dialog)
    dialog.show()
    qtbot.waitExposed(dialog)
    dialog.import_table(MEDIDOR_CALIB, "barometer")
    qtbot.waitUntil(lambda: dialog.calibration is not None, timeout=SIGNAL_TIMEOUT_MS)
    assert dialog.calibration.slope == pytest.approx(1.6492, abs=1e-4)
    assert dialog.camera.text() == (
        "dji-mavic-air2-2.7k: focal 7.6 mm, sensor 6.4 mm, 2688 px wide (preset "
        "'dji-mavic-air2-2.7k': calib.xlsx names Mavic Air 2 at 2.7k)")
    assert [(box.isEnabled(), box.isChecked()) for box in dialog.clip_boxes.values()] == [
        (False, False), (True, False)]

    other = tmp_path / "mavic3.csv"
    pd.read_excel(MEDIDOR_CALIB).assign(flen=fhd.focal_mm, sw=fhd.sensor_width_mm,
                                        iw=fhd.image_width_px).to_csv(other, index=False)
    dialog.import_table(other, "barometer")
    qtbot.waitUntil(lambda: "one calibration holds for one camera" in dialog.status.text(),
                    timeout=SIGNAL_TIMEOUT_MS)
    assert dialog.table.rowCount() == 351 and dialog.calibration.num_shots == 351
