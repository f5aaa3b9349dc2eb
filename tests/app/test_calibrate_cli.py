"""`dolphinfit calibrate altitude` on real calibration sets, and its use by `measure`."""

import json
from pathlib import Path

import cv2
import numpy as np
import pandas as pd
import pytest

from dolphinfit.app.cli import main
from dolphinfit.core.io.calibration_table import read_calibration_table
from dolphinfit.core.io.medidor import read_medidor
from dolphinfit.core.measure.altitude_calibration import (
    fit_altitude_calibration,
    read_altitude_calibration,
)
from tests.app.test_measure_cli import ALTITUDE_M, BL_M, CAMERA, _annotation_file, _result

REAL = Path(__file__).resolve().parents[1] / "data" / "real"
MEDIDOR_CALIB = REAL / "medidor" / "calib.xlsx"
DEFAULT_LENS_PRESET = "dji-mavic3-5.1k"   # a bundled preset of another video mode
# MedidoR's GUI test enters the Mavic Air 2's camera so (tests/data/real/medidor/test-app-*.R)
MEDIDOR_CAMERA = ["--focal-mm", "7.6", "--sensor-width-mm", "6.4", "--image-width", "2688"]
MEDIDOR_FOCAL_PX = 7.6 * 2688 / 6.4


def _calibrate(tmp_path: Path, table: Path, *options: str) -> dict:
    out = tmp_path / "cal.json"
    assert main(["calibrate", "altitude", str(table), "--out", str(out), *options]) == 0
    return json.loads(out.read_text(encoding="utf-8"))


def test_medidor_calibration_set_gives_medidors_own_scale(tmp_path, capsys):
    """351 real shots of a 2.02 m object at 10–52 m: the line is MedidoR's lm(eGSD ~ C_Alt)
    times the focal length in pixels (its eGSD column is rounded to 0.1 mm/px, hence 0.5 %),
    and it gives the metres per pixel MedidoR applied to the right whale at 23 m (cGSD in its
    measurement sheet) to 0.05 %: 13.75 m of whale, where the camera as entered says 8.44."""
    plot = tmp_path / "cal.png"
    cal = _calibrate(tmp_path, MEDIDOR_CALIB, "--object-length", "2.02", *MEDIDOR_CAMERA,
                     "--plot", str(plot))
    assert "1.6492 × recorded" in capsys.readouterr().out
    assert plot.stat().st_size > 10_000
    assert (cal["num_shots"], cal["drone"], cal["altimeter"]) == (351, "Mavic Air 2", "C_Alt")
    assert cal["slope"] == pytest.approx(1.6492, abs=1e-4)
    assert cal["intercept_m"] == pytest.approx(-0.468, abs=1e-3)
    assert cal["residual_sd_fraction"] == pytest.approx(0.0174, abs=1e-4)
    assert cal["slope_ci"][0] < cal["slope"] < cal["slope_ci"][1]
    sheet = pd.read_excel(MEDIDOR_CALIB)
    gsd_slope, gsd_intercept = np.polyfit(sheet["C_Alt"], sheet["eGSD"], 1)
    assert cal["slope"] / MEDIDOR_FOCAL_PX == pytest.approx(gsd_slope, rel=5e-3)
    calibration = read_altitude_calibration(tmp_path / "cal.json")
    (whale, *_) = read_medidor(REAL / "medidor" / "Measurements_10.xlsx")
    gsd = calibration.true_altitude(whale.altitude_m) / MEDIDOR_FOCAL_PX
    assert gsd == pytest.approx(whale.gsd_m_per_px, rel=5e-4)
    assert whale.length_px * gsd == pytest.approx(13.75, abs=0.01)
    assert whale.length_px * whale.altitude_m / MEDIDOR_FOCAL_PX == pytest.approx(8.44, abs=0.01)


def test_medidor_calibration_agrees_with_collatrix_method_5():
    """CollatriX v1's altitude_calib (Burnett et al. 2018, method 5) first smooths the pixel
    lengths on a log-log line, then fits the same straight line: its altitudes over 10–50 m
    lie within 0.9 % of ours on the same shots (most at 10 m), half the spread of one shot."""
    table = read_calibration_table(MEDIDOR_CALIB)
    ours = fit_altitude_calibration(table, 2.02, _medidor_camera())
    recorded = np.array([s.recorded_altitude_m for s in table.shots])
    pixels = np.array([s.pixel_length for s in table.shots])
    smooth = 10 ** np.polyval(np.polyfit(np.log10(recorded), np.log10(pixels), 1),
                              np.log10(recorded))
    collatrix = np.polyfit(recorded, 2.02 * MEDIDOR_FOCAL_PX / smooth, 1)
    altitudes = np.linspace(10, 50, 9)
    np.testing.assert_allclose(ours.true_altitude(altitudes), np.polyval(collatrix, altitudes),
                               rtol=9e-3)


def _medidor_camera():
    from dolphinfit.core.measure.altitude_calibration import CalibrationCamera

    return CalibrationCamera(7.6, 6.4, 2688)


@pytest.mark.parametrize("altimeter, slope, spread, bias", [
    ("laser", 1.0127, 0.0212, -0.329), ("barometer", 1.0574, 0.0124, -2.860)])
def test_xcertainty_calibration2_both_altimeters(tmp_path, altimeter, slope, spread, bias):
    """Xcertainty's `calibration2` (46 shots of a 1.48 m object from a LemHex, 11–117 m, camera
    and length in the table): the laser reads 1.3 % low (slope 1.013), the barometer 5.7 %;
    Xcertainty's bias-only estimate is the mean of recorded minus implied altitude."""
    cal = _calibrate(tmp_path, REAL / "xcertainty" / "calibration2.rda",
                     "--altimeter", altimeter)
    assert (cal["num_shots"], cal["object_length_m"], cal["camera"]["focal_mm"]) == \
        (46, 1.48, 35.0)
    assert cal["slope"] == pytest.approx(slope, abs=1e-4)
    assert cal["residual_sd_fraction"] == pytest.approx(spread, abs=1e-4)
    assert cal["bias_only_m"] == pytest.approx(bias, abs=1e-3)


def test_known_offset_and_scale_are_recovered(tmp_path):
    """Shots made from a known line (true = 0.8 m + 1.03 × recorded) with 1 % noise on the
    pixel lengths: both are recovered inside their 95 % intervals, the spread is 1 %."""
    rng = np.random.default_rng(3)
    recorded = np.repeat(np.arange(10.0, 55.0, 5.0), 8)
    true = 0.8 + 1.03 * recorded
    focal_px = CAMERA.intrinsics().focal_px
    pixels = 1.5 * focal_px / true * (1 + 0.01 * rng.standard_normal(recorded.size))
    table = tmp_path / "shots.csv"
    pd.DataFrame({"image": [f"img{i}" for i in range(recorded.size)], "altitude_m": recorded,
                  "pixel_length": pixels}).to_csv(table, index=False)
    cal = _calibrate(tmp_path, table, "--object-length", "1.5", "--focal-mm", "12.29",
                     "--sensor-width-mm", "4.3175", "--image-width", "1280")
    assert cal["intercept_ci_m"][0] < 0.8 < cal["intercept_ci_m"][1]
    assert cal["slope_ci"][0] < 1.03 < cal["slope_ci"][1]
    assert cal["residual_sd_fraction"] == pytest.approx(0.01, rel=0.15)
    assert cal["outliers"] == []


def _synthetic_calibration(tmp_path: Path) -> Path:
    """A calibration of the measure tests' camera: true = 0.5 m + 1.02 × recorded, 1 % spread."""
    rng = np.random.default_rng(0)
    recorded = np.repeat(np.arange(10.0, 45.0, 5.0), 6)
    focal_px = CAMERA.intrinsics().focal_px
    pixels = 2.0 * focal_px / (0.5 + 1.02 * recorded) * (1 + 0.01 * rng.standard_normal(
        recorded.size))
    table = tmp_path / "shots.csv"
    pd.DataFrame({"altitude_m": recorded, "pixel_length": pixels, "object_length_m": 2.0,
                  "focal_mm": CAMERA.focal_mm, "sensor_width_mm": CAMERA.sensor_width_mm,
                  "image_width_px": CAMERA.image_width_px}).to_csv(table, index=False)
    out = tmp_path / "cal.json"
    assert main(["calibrate", "altitude", str(table), "--out", str(out)]) == 0
    return out


def test_measure_with_a_calibration_corrects_the_altitude_and_narrows_the_interval(
        tmp_path, capsys):
    """The annotation's recorded 20 m becomes the line's 20.9 m: the length grows by that
    ratio; with a barometer's default ±5 % the volume's interval is some 3× wider than with
    the calibration's ~1 %; the result keeps the recorded altitude."""
    path = _annotation_file(tmp_path)
    cal = _synthetic_calibration(tmp_path)
    calibration = read_altitude_calibration(cal)
    widths = {}
    for name, options in (("plain", []), ("calibrated", ["--altitude-calibration", str(cal)])):
        out = tmp_path / name
        assert main(["measure", str(path), "--out", str(out), "--mc", "2000",
                     "--altitude-source", "barometer", *options]) == 0
        result = _result(out)
        interval = result["uncertainty"]["volume_m3"]
        widths[name] = (interval["high"] - interval["low"]) / result["volume_m3"]
    expected = calibration.true_altitude(ALTITUDE_M)
    assert expected == pytest.approx(20.9, abs=0.1)
    assert result["altitude_m"] == pytest.approx(expected, rel=1e-9)
    assert result["recorded_altitude_m"] == ALTITUDE_M
    assert result["length_m"] == pytest.approx(BL_M * expected / ALTITUDE_M, rel=1e-9)
    assert widths["plain"] > 2.5 * widths["calibrated"]
    assert "recorded → 20.9" in capsys.readouterr().out


def test_measure_refuses_a_calibration_of_another_camera(tmp_path, capsys):
    path = _annotation_file(tmp_path)
    cal = tmp_path / "medidor.json"
    assert main(["calibrate", "altitude", str(MEDIDOR_CALIB), "--out", str(cal),
                 "--object-length", "2.02", *MEDIDOR_CAMERA]) == 0
    assert main(["measure", str(path), "--altitude-calibration", str(cal)]) == 2
    assert "holds only for its own camera" in capsys.readouterr().err


@pytest.mark.parametrize("options, message", [
    (["--object-length", "2.0", *MEDIDOR_CAMERA], "differs from --object-length 2"),
    (["--object-length", "2.02"], "the table has no focal mm; give --focal-mm"),
    (["--object-length", "2.02", "--focal-mm", "7.6"], "give --sensor-width-mm, --image-width"),
    (["--object-length", "2.02", "--camera", "dji-mavic3-2.7k", "--focal-mm", "4"],
     "not both"),
    (["--object-length", "2.02", *MEDIDOR_CAMERA, "--drone", "Mavic 3"], "no drone 'Mavic 3'"),
    (["--object-length", "2.02", *MEDIDOR_CAMERA, "--altimeter", "laser"], "no laser altitudes"),
    (["--object-length", "-2", *MEDIDOR_CAMERA], "--object-length"),
])
def test_bad_options_exit_2_naming_them(tmp_path, capsys, options, message):
    assert main(["calibrate", "altitude", str(MEDIDOR_CALIB), "--out",
                 str(tmp_path / "cal.json"), *options]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "cal.json").exists()


@pytest.mark.parametrize("table, message", [
    ("two_altimeters", "say which with --altimeter"),
    ("few", "a calibration needs at least 5"),
    ("narrow", "span only 20–21 m"),
    ("text", "row 3: pixel_length 'abc' is not a number"),
    ("no_pixels", "no pixel-length column"),
])
def test_bad_tables_exit_2_naming_them(tmp_path, capsys, table, message):
    base = {"altitude_m": [10.0, 20.0, 30.0, 40.0, 50.0, 60.0],
            "pixel_length": [300.0, 150.0, 100.0, 75.0, 60.0, 50.0]}
    frame = {
        "two_altimeters": {"Baro_Alt": base["altitude_m"], "Laser_Alt": base["altitude_m"],
                           "Lpix": base["pixel_length"]},
        "few": {key: values[:4] for key, values in base.items()},
        "narrow": {"altitude_m": [20.0, 20.2, 20.4, 20.6, 20.8, 21.0],
                   "pixel_length": base["pixel_length"]},
        "text": {**base, "pixel_length": [300.0, "abc", 100.0, 75.0, 60.0, 50.0]},
        "no_pixels": {"altitude_m": base["altitude_m"]},
    }[table]
    path = tmp_path / "shots.csv"
    pd.DataFrame(frame).to_csv(path, index=False)
    assert main(["calibrate", "altitude", str(path), "--out", str(tmp_path / "cal.json"),
                 "--object-length", "1", *MEDIDOR_CAMERA]) == 2
    assert message in capsys.readouterr().err


def test_a_damaged_calibration_file_is_refused(tmp_path, capsys):
    path = _annotation_file(tmp_path)
    cal = _synthetic_calibration(tmp_path)
    doc = json.loads(cal.read_text(encoding="utf-8"))
    doc["slope"] = -1.0
    cal.write_text(json.dumps(doc), encoding="utf-8")
    assert main(["measure", str(path), "--altitude-calibration", str(cal)]) == 2
    assert "slope" in capsys.readouterr().err
    (tmp_path / "other.json").write_text('{"format": "something"}', encoding="utf-8")
    assert main(["measure", str(path), "--altitude-calibration",
                 str(tmp_path / "other.json")]) == 2
    assert "is no altitude calibration" in capsys.readouterr().err


def test_calibrate_lens_from_board_images_and_measure_through_it(tmp_path, capsys,
                                                                 monkeypatch):
    """Nine board images through a barrel lens: the lens is written; an annotation clicked in
    the frame's corner is warned about without it, and measures longer through it (a barrel
    lens shrinks what lies off-centre). Kept with a camera preset (`camera lens`), it is
    used for an annotation of that preset without --lens."""
    monkeypatch.setenv("DOLPHINFIT_CONFIG_DIR", str(tmp_path / "config"))
    from tests.core.measure.test_lens import BOARD, board_views

    paths = []
    for i, view in enumerate(board_views()):
        paths.append(tmp_path / f"board_{i}.png")
        cv2.imwrite(str(paths[-1]), view)
    lens = tmp_path / "lens.json"
    assert main(["calibrate", "lens", *map(str, paths), "--board", f"{BOARD[0]}x{BOARD[1]}",
                 "--square-mm", "30", "--out", str(lens)]) == 0
    assert "k1 -0.1" in capsys.readouterr().out
    annotation = _annotation_file(tmp_path)
    doc = json.loads(annotation.read_text(encoding="utf-8"))
    doc["midline_px"] = [[u + 380.0, v + 300.0] for u, v in doc["midline_px"]]   # the corner
    annotation.write_text(json.dumps(doc), encoding="utf-8")
    lengths = {}
    for name, options in (("plain", []), ("lens", ["--lens", str(lens)])):
        assert main(["measure", str(annotation), "--out", str(tmp_path / name), "--mc", "0",
                     *options]) == 0
        result = _result(tmp_path / name)
        lengths[name] = result["length_m"]
        assert any("without a lens model" in w for w in result["warnings"]) == (name == "plain")
    assert 1.01 < lengths["lens"] / lengths["plain"] < 1.1
    assert any("camera says 3644 px" in w for w in result["warnings"])   # 900 px calibrated
    assert main(["camera", "add", "crop-rig", "--sensor-width-mm", str(CAMERA.sensor_width_mm),
                 "--focal-mm", str(CAMERA.focal_mm), "--width-px", "1280", "--height-px",
                 "720"]) == 0
    assert main(["camera", "lens", "crop-rig", str(lens)]) == 0
    assert main(["camera", "show", "crop-rig"]) == 0
    assert "crop-rig.json" in capsys.readouterr().out
    doc["camera"] = {"preset": "crop-rig"}
    annotation.write_text(json.dumps(doc), encoding="utf-8")
    assert main(["measure", str(annotation), "--out", str(tmp_path / "preset"), "--mc",
                 "0"]) == 0
    assert "clicks taken through the lens model of 'crop-rig'" in capsys.readouterr().out
    assert _result(tmp_path / "preset")["length_m"] == pytest.approx(lengths["lens"], rel=1e-9)
    assert main(["camera", "lens", "crop-rig", "--remove"]) == 0
    assert main(["camera", "lens", DEFAULT_LENS_PRESET, str(lens)]) == 2
    assert "calibrated on 1280×720 px images; these are 5120×2700" in capsys.readouterr().err
    assert main(["calibrate", "lens", *map(str, paths[:3]), "--board", "9x6", "--square-mm",
                 "30", "--out", str(tmp_path / "few.json")]) == 2
    assert "at least 5 views" in capsys.readouterr().err
    assert main(["calibrate", "lens", str(paths[0]), "--board", "nine", "--square-mm", "30",
                 "--out", str(tmp_path / "bad.json")]) == 2
    assert "expected the inner corners as COLSxROWS" in capsys.readouterr().err


def test_a_projects_calibration_is_fitted_headless(tmp_path, capsys):
    """The set made in the app, from the project file: the same line as the app fits; its
    own object and camera, so options that would contradict them are refused."""
    from dolphinfit.core.project.calibrations import fitted_calibration
    from dolphinfit.core.project.model import Project
    from dolphinfit.core.project.project_file import write_project
    from tests.core.project.test_calibrations import calibration_set

    calibration = calibration_set(CAMERA)
    project = tmp_path / "survey.dolphinfit"
    write_project(project, Project(calibrations=(calibration,)))
    cal = _calibrate(tmp_path, project)
    assert cal["slope"] == pytest.approx(fitted_calibration(calibration).slope, rel=1e-12)
    assert cal["num_shots"] == 12 and cal["drone"] == "test drone barometer"
    assert main(["calibrate", "altitude", str(project), "--out", str(tmp_path / "x.json"),
                 "--object-length", "2"]) == 2
    assert "drop --object-length" in capsys.readouterr().err
    assert main(["calibrate", "altitude", str(project), "--out", str(tmp_path / "x.json"),
                 "--drone", "other"]) == 2
    assert "no calibration 'other'" in capsys.readouterr().err
