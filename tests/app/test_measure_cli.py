"""`dolphinfit measure` driven through app.cli.main on annotations and MorphoMetriX files."""

import csv
import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.app.cli import main
from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.measure.annotation_json import AnnotationFile, write_annotation_json
from dolphinfit.core.measure.morphometrix import read_morphometrix
from dolphinfit.core.measure.annotation import Annotation, Calibration
from dolphinfit.core.measure.elliptical import TAIL_EXTRAPOLATED, TAIL_MEASURED, elliptical_volume
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.stations import STATION_FRACTIONS
from dolphinfit.core.measure.xcertainty import MEASUREMENT_COLUMNS

V2_DEMO = Path(__file__).resolve().parents[1] / "data" / "morphometrix" / \
    "mmx_v2_demo-annotated.csv"
# Provisional template widths / BL (reference/morphometrics.md §4)
W_BL = np.array([.045, .085, .13, .15, .165, .175, .18, .18, .175, .16, .14, .125, .11, .09,
                 .075, .06, .045, .030, .015])
BL_M, ALTITUDE_M = 2.5, 20.0
# The paper's lens over a 1280 px crop of its 5.1K mode: focal 3643.6 px, as on the full frame.
CAMERA = CameraPreset("crop", "", 12.29, 17.27 / 4, 1280, 720, "test", False)
M_PER_PX = ALTITUDE_M / CAMERA.intrinsics().focal_px
ORIGIN_PX = np.array([400.0, 360.0])


def _annotation_file(tmp_path: Path) -> Path:
    """A straight 2.5 m dolphin with the §4 widths, seen at 20 m: 455 px long."""
    length_px = BL_M / M_PER_PX
    u = ORIGIN_PX[0] + STATION_FRACTIONS * length_px
    half = W_BL * BL_M / M_PER_PX / 2
    edges = np.stack([np.stack([u, ORIGIN_PX[1] - half], 1),
                      np.stack([u, ORIGIN_PX[1] + half], 1)], axis=1)
    midline = np.stack([ORIGIN_PX, ORIGIN_PX + [length_px, 0.0]])
    doc = AnnotationFile(Annotation(0, midline, edges),
                         Calibration(CAMERA, None, ALTITUDE_M, "laser"), image_id="T1 f0")
    path = tmp_path / "t1.json"
    write_annotation_json(path, doc)
    return path


def _result(out_dir: Path, stem: str = "t1") -> dict:
    return json.loads((out_dir / f"{stem}_measure.json").read_text(encoding="utf-8"))


def _expected_volume(tail=TAIL_EXTRAPOLATED, hw=None):
    ratios = load_hw_preset().completed()[0] if hw is None else hw
    return float(elliptical_volume(BL_M, W_BL * BL_M, ratios, tail))


def test_measure_prints_the_table_and_writes_three_exports(tmp_path, capsys):
    """Exit 0; length, volume (V/BL³ = 0.0148), BCI and mass with intervals; JSON, MorphoMetriX
    and wide CSV written; the same seed gives the same numbers."""
    path = _annotation_file(tmp_path)
    out = tmp_path / "out"
    assert main(["measure", str(path), "--out", str(out), "--mc", "300"]) == 0
    text = capsys.readouterr().out
    assert "95 % interval (300 draws)" in text and "mass_kg" in text and "provisional" in text
    result = _result(out)
    assert result["length_m"] == pytest.approx(BL_M, rel=1e-12)
    assert result["volume_m3"] == pytest.approx(_expected_volume(), rel=1e-12)
    assert result["volume_m3"] / BL_M**3 == pytest.approx(0.0148, abs=5e-5)
    assert result["bci"] == pytest.approx(0.1994, abs=1e-4)
    assert result["altitude_source"] == "laser" and result["seed"] == 0
    interval = result["uncertainty"]["volume_m3"]
    assert interval["low"] < result["volume_m3"] < interval["high"]
    assert len(result["uncertainty"]["widths_m"]["sd"]) == 19
    record = read_morphometrix(out / "t1_mmx.csv")
    assert record.lengths_m["TL"] == pytest.approx(BL_M, rel=1e-9)
    assert record.widths_px["TL"][50.0] == pytest.approx(0.16 * BL_M / M_PER_PX, rel=1e-9)
    with open(out / "t1_wide.csv", newline="", encoding="utf-8") as file:
        (row,) = list(csv.DictReader(file))
    assert float(row["BVell_5perc"]) == pytest.approx(result["volume_m3"], rel=1e-9)
    assert (row["Iw"], row["Sw"], row["Laser_Alt"], row["TL_ratio85.00"]) == \
        ("1280", "4.3175", "20", "2.4")
    assert float(row["mass_kg_hi95"]) > float(row["mass_kg"]) > float(row["mass_kg_lo95"])
    # the row Xcertainty reads: its columns in its order, pixels as measured
    with open(out / "t1_xcertainty.csv", newline="", encoding="utf-8") as file:
        reader = csv.DictReader(file)
        (row,) = list(reader)
    assert tuple(reader.fieldnames) == MEASUREMENT_COLUMNS
    assert (row["whale_ID"], row["image"], row["Iw"], row["Sw"], row["Laser_Alt"],
            row["Baro_Alt"]) == ("T1 f0", "T1 f0", "1280", "4.3175", "20", "")
    assert float(row["TL_px"]) == pytest.approx(BL_M / M_PER_PX, rel=1e-9)
    assert float(row["TL_w50.00_px"]) == pytest.approx(0.16 * BL_M / M_PER_PX, rel=1e-9)
    assert main(["measure", str(path), "--out", str(tmp_path / "again"), "--mc", "300",
                 "--subject", "Tt-0042"]) == 0
    assert _result(tmp_path / "again", "t1")["uncertainty"] == result["uncertainty"]
    with open(tmp_path / "again" / "t1_xcertainty.csv", newline="", encoding="utf-8") as file:
        assert next(csv.DictReader(file))["whale_ID"] == "Tt-0042"


def test_a_corrected_altitude_rescales_every_length(tmp_path):
    """--altitude-m 25 instead of 20: length × 1.25, volume × 1.25³, no re-annotation."""
    path = _annotation_file(tmp_path)
    assert main(["measure", str(path), "--mc", "0", "--altitude-m", "25"]) == 0
    result = _result(tmp_path)
    assert result["length_m"] == pytest.approx(BL_M * 1.25, rel=1e-12)
    assert result["volume_m3"] == pytest.approx(_expected_volume() * 1.25**3, rel=1e-12)


def test_measured_tail_circular_ratios_and_no_monte_carlo(tmp_path):
    """--tail measured --hw circular --mc 0: the circular measured-tail volume, no interval."""
    path = _annotation_file(tmp_path)
    assert main(["measure", str(path), "--tail", "measured", "--hw", "circular",
                 "--mc", "0"]) == 0
    result = _result(tmp_path)
    assert result["volume_m3"] == pytest.approx(_expected_volume(TAIL_MEASURED, np.ones(19)),
                                                rel=1e-12)
    assert result["volume_m3"] == pytest.approx(result["volume_circular_m3"], rel=1e-12)
    assert result["uncertainty"] is None and result["settings"]["tail"] == "measured"


def test_mass_model_constants_from_a_file(tmp_path):
    """A JSON override of α changes density and mass but not BCI."""
    path = _annotation_file(tmp_path)
    model = tmp_path / "model.json"
    model.write_text(json.dumps({"density_intercept_kg_m3": 1025.0,
                                 "bci_fit_range": [-0.1, 0.1]}), encoding="utf-8")
    assert main(["measure", str(path), "--mc", "0", "--mass-model", str(model)]) == 0
    result = _result(tmp_path)
    assert result["mass_kg"] == pytest.approx(
        result["volume_m3"] * (1025.0 - 278.12 * result["bci"]), rel=1e-12)
    assert result["is_bci_outside_fit_range"] is True
    assert any("outside -0.1…+0.1" in w for w in result["warnings"])


def test_widths_from_the_mask(tmp_path):
    """--from-mask on the rasterised outline: widths within 1 px, volume within 2 %."""
    path = _annotation_file(tmp_path)
    v, u = np.mgrid[:720, :1280].astype(float)
    at = ORIGIN_PX[0] + np.concatenate([[0.0], STATION_FRACTIONS, [1.0]]) * BL_M / M_PER_PX
    half = np.interp(u, at, np.concatenate([[0.0], W_BL, [0.0]]) * BL_M / M_PER_PX / 2)
    masks = tmp_path / "masks"
    masks.mkdir()
    mask = (np.abs(v - ORIGIN_PX[1]) <= half) * np.uint8(255)
    cv2.imwrite(str(masks / "000000.png"), mask)
    cv2.imwrite(str(tmp_path / "still_mask.png"), mask)  # a still's mask: one image file
    for source in (masks, tmp_path / "still_mask.png"):
        assert main(["measure", str(path), "--mc", "0", "--from-mask", str(source)]) == 0
        result = _result(tmp_path)
        widths_px = np.array([s["width_px"] for s in result["stations"]])
        np.testing.assert_allclose(widths_px, W_BL * BL_M / M_PER_PX, atol=1.0)
        assert result["volume_m3"] == pytest.approx(_expected_volume(), rel=0.02)


def test_morphometrix_file_as_input(tmp_path, capsys):
    """The v2 demo (a 7.97 m whale, 10 % widths) runs; 5 % stations are filled and flagged,
    and a whale's BCI under the dolphin mass model is flagged as outside the fit range."""
    assert main(["measure", str(V2_DEMO), "--out", str(tmp_path), "--mc", "50"]) == 0
    assert "altitude source unknown" in capsys.readouterr().out
    result = _result(tmp_path, V2_DEMO.stem)
    assert result["length_m"] == pytest.approx(7.9665, abs=1e-4)
    assert result["stations"][1]["width_px"] == 152.3
    assert [s["is_filled"] for s in result["stations"][:3]] == [True, False, True]
    assert result["is_bci_outside_fit_range"] and result["altitude_source"] == "manual"
    assert any("filled by linear interpolation: 5 %, 15 %" in w for w in result["warnings"])


@pytest.mark.parametrize("argv, message", [
    (["--mc", "1"], "--mc must be 0"),
    (["--hw", "orca"], "unknown HW ratio preset 'orca'"),
    (["--altitude-m", "-2"], "--altitude-m: -2 m is outside the plausible range 1–500 m"),
    (["--digitisation-sd-px", "-1"], "--digitisation-sd-px: must be at least 0, got -1"),
    (["--from-mask", "MISSING"], "no such file or folder"),
])
def test_bad_options_exit_2(tmp_path, capsys, argv, message):
    """Out-of-range options and unknown tables give exit 2 with a message."""
    path = _annotation_file(tmp_path)
    argv = [a.replace("MISSING", str(tmp_path / "none")) for a in argv]
    assert main(["measure", str(path), *argv]) == 2
    assert message in capsys.readouterr().err


def test_bad_inputs_exit_2_naming_the_file(tmp_path, capsys):
    """A missing annotation, a mask of the wrong size and --from-mask on a CSV exit 2."""
    assert main(["measure", str(tmp_path / "none.json")]) == 2
    assert "none.json: cannot read" in capsys.readouterr().err
    path = _annotation_file(tmp_path)
    masks = tmp_path / "masks"
    masks.mkdir()
    cv2.imwrite(str(masks / "000000.png"), np.eye(10, dtype=np.uint8) * 255)
    assert main(["measure", str(path), "--from-mask", str(masks)]) == 2
    assert "masks are 10×10 px but the camera's frames are 1280×720 px" in \
        capsys.readouterr().err
    assert main(["measure", str(V2_DEMO), "--from-mask", str(masks)]) == 2
    assert "--from-mask needs an annotation" in capsys.readouterr().err
