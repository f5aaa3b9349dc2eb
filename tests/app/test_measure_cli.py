"""`dolphinfit measure` driven through app.cli.main on annotations and MorphoMetriX files."""

import csv
import json
from pathlib import Path

import cv2
import numpy as np
import pandas as pd
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
MINKE = Path(__file__).resolve().parents[1] / "data" / "real" / "minke"
# The two people's MorphoMetriX v1 measurements of the minke, as written in their files
MINKE_PEOPLE = {
    "demo-annotated": (7.593, dict(zip(range(5, 100, 5), (
        0.479, 0.693, 0.869, 1.084, 1.106, 1.172, 1.243, 1.259, 1.184, 1.136, 1.043, 0.929,
        0.809, 0.65, 0.504, 0.357, 0.224, 0.169, 0.942)))),
    "test-image": (7.547, dict(zip(range(10, 100, 10), (
        0.684, 1.086, 1.186, 1.257, 1.139, 0.941, 0.657, 0.363, 0.156)))),
}
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


@pytest.mark.parametrize("name", MINKE_PEOPLE)
def test_the_minke_files_as_people_wrote_them(tmp_path, capsys, name):
    """Both people's v1 files (Total_Length, Total Length) measure: their length and every
    width they wrote, station by station, in the MorphoMetriX export (as TL) and, to 85 %
    (the default tail extrapolates 90/95 %), in the result."""
    length_m, widths_m = MINKE_PEOPLE[name]
    widths_m = {float(pct): w for pct, w in widths_m.items()}
    argv = ["measure", str(MINKE / f"{name}.csv"), "--out", str(tmp_path), "--mc", "0"]
    assert main(argv) == 0
    assert "exported as TL" in capsys.readouterr().out
    result = _result(tmp_path, name)
    assert result["length_m"] == pytest.approx(length_m, rel=1e-9)
    body = {s["station_pct"]: s["width_m"] for s in result["stations"]
            if not s["is_filled"] and s["station_pct"] <= 85}
    assert body == pytest.approx({p: w for p, w in widths_m.items() if p <= 85}, rel=1e-9)
    record = read_morphometrix(tmp_path / f"{name}_mmx.csv")
    assert record.lengths_m == pytest.approx({"TL": length_m}, rel=1e-9)
    assert record.widths_m["TL"] == pytest.approx(widths_m, rel=1e-9)


def test_people_files_pool_with_ours(tmp_path):
    """Our CollatriX table and the two people's have the same columns; pooled, the three TLs
    are 2.5, 7.593 and 7.547 m."""
    tables = []
    for path in (_annotation_file(tmp_path), MINKE / "demo-annotated.csv",
                 MINKE / "test-image.csv"):
        assert main(["measure", str(path), "--out", str(tmp_path), "--mc", "0"]) == 0
        tables.append(pd.read_csv(tmp_path / f"{path.stem}_collatrix.csv"))
    assert all(list(table.columns) == list(tables[0].columns) for table in tables)
    pooled = pd.concat(tables, ignore_index=True)
    assert pooled.shape == (3, len(tables[0].columns))
    np.testing.assert_allclose(pooled["TL"], [BL_M, 7.593, 7.547], rtol=1e-9)


def test_morphometrix_v1_export(tmp_path, capsys):
    """--mmx-version 1 writes MorphoMetriX v1 blocks (and says so): read back, the same metres
    as the v2 export."""
    path = _annotation_file(tmp_path)
    assert main(["measure", str(path), "--mc", "0", "--out", str(tmp_path / "v2")]) == 0
    assert main(["measure", str(path), "--mc", "0", "--out", str(tmp_path / "v1"),
                 "--mmx-version", "1"]) == 0
    assert "t1_mmx.csv (MorphoMetriX v1)" in capsys.readouterr().out
    v1 = read_morphometrix(tmp_path / "v1" / "t1_mmx.csv")
    v2 = read_morphometrix(tmp_path / "v2" / "t1_mmx.csv")
    assert (v1.version, v2.version) == (1, 2) and not v1.lengths_px
    assert v1.lengths_m == pytest.approx(v2.lengths_m, rel=1e-9)
    assert v1.widths_m["TL"] == pytest.approx(v2.widths_m["TL"], rel=1e-9)
    assert (tmp_path / "v1" / "t1_mmx.csv").read_text().splitlines()[7].startswith(
        "Object,Length (m),5.00% Width,10.00% Width")


def test_length_name_option(tmp_path, capsys):
    """--length-name matches whatever the case and spacing; a name not in the file, or two
    total lengths, exit 2 naming the file and its lengths."""
    test_image = MINKE / "test-image.csv"
    assert main(["measure", str(test_image), "--out", str(tmp_path), "--mc", "0",
                 "--length-name", "TOTAL_length"]) == 0
    assert _result(tmp_path, "test-image")["length_m"] == pytest.approx(7.547, rel=1e-9)
    assert main(["measure", str(test_image), "--out", str(tmp_path), "--length-name",
                 "body"]) == 2
    assert "test-image.csv: no length named 'body' among its lengths (Total Length, " \
        "Fluke_span)" in capsys.readouterr().err
    both = tmp_path / "both.csv"
    text = test_image.read_text(encoding="utf-8")
    both.write_text(text.replace("Fluke_span,2.225", "TL,7.6"), encoding="utf-8")
    assert main(["measure", str(both), "--out", str(tmp_path)]) == 2
    assert "both.csv: several total lengths (Total Length, TL)" in capsys.readouterr().err


def _mask_image(tmp_path: Path) -> Path:
    """The straight 2.5 m dolphin of _annotation_file as a 1280×720 mask image."""
    v, u = np.mgrid[:720, :1280].astype(float)
    at = ORIGIN_PX[0] + np.concatenate([[0.0], STATION_FRACTIONS, [1.0]]) * BL_M / M_PER_PX
    half = np.interp(u, at, np.concatenate([[0.0], W_BL, [0.0]]) * BL_M / M_PER_PX / 2)
    path = tmp_path / "still_mask.png"
    cv2.imwrite(str(path), (np.abs(v - ORIGIN_PX[1]) < half) * np.uint8(255))
    return path


def test_from_mask_alone(tmp_path):
    """--from-mask without an annotation: the midline from the mask, the camera and altitude
    of the options; the 2.5 m dolphin within 0.5 %, widths within 1.5 px, volume within 2 %."""
    mask = _mask_image(tmp_path)
    assert main(["measure", "--from-mask", str(mask), "--altitude-m", str(ALTITUDE_M),
                 "--sensor-width-mm", str(CAMERA.sensor_width_mm),
                 "--focal-mm", str(CAMERA.focal_mm), "--mc", "0"]) == 0
    result = _result(tmp_path, "still_mask")
    assert result["length_m"] == pytest.approx(BL_M, rel=0.005)
    assert result["altitude_source"] == "manual"
    widths_px = np.array([s["width_px"] for s in result["stations"]])
    np.testing.assert_allclose(widths_px, W_BL * BL_M / M_PER_PX, atol=1.5)
    assert result["volume_m3"] == pytest.approx(_expected_volume(), rel=0.02)
    assert (tmp_path / "still_mask_xcertainty.csv").is_file()


@pytest.mark.parametrize("argv, message", [
    ([], "give an annotation (.json), a MorphoMetriX file (.csv) or --from-mask MASKS"),
    (["--from-mask", "MASK", "--camera", "dji-mavic3-5.1k"],
     "--from-mask without an annotation needs --altitude-m"),
    (["--from-mask", "MASK", "--altitude-m", "20", "--focal-mm", "12.29"],
     "needs its camera: --camera PRESET or both --sensor-width-mm and --focal-mm"),
    (["--from-mask", "MASK", "--altitude-m", "20", "--camera", "dji-mavic3-5.1k"],
     "but the clip is 1280×720 px"),
    (["--from-mask", "MASK", "--altitude-m", "20", "--camera", "dji-mavic3-5.1k",
      "--frame", "3"], "no animal in the mask of frame 3 (1 frames)"),
    (["ANNOTATION", "--camera", "dji-mavic3-5.1k"], "--camera is for --from-mask without"),
])
def test_from_mask_alone_needs_altitude_and_camera(tmp_path, capsys, argv, message):
    """Without an annotation a mask needs --altitude-m and one camera; a preset of another
    frame size and a frame without the animal exit 2."""
    argv = [a.replace("MASK", str(_mask_image(tmp_path))) if a == "MASK"
            else str(_annotation_file(tmp_path)) if a == "ANNOTATION" else a for a in argv]
    assert main(["measure", *argv]) == 2
    assert message in capsys.readouterr().err
