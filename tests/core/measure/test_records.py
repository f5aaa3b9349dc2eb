"""Tests for core/measure/records.py: one annotated frame to the result JSON and the exports."""

import csv
import json
from dataclasses import replace

import numpy as np
import pytest

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation_json import AnnotationFile
from dolphinfit.core.measure.morphometrix import read_morphometrix
from dolphinfit.core.measure.annotation import Annotation, Calibration
from dolphinfit.core.measure.baseline import BaselineSettings, estimate_baseline
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.records import (
    RESULT_SCHEMA_VERSION, default_error_model, mass_model_from_json,
    collatrix_csv_row, measured_image_from_annotation, result_record, wide_csv_row,
    write_exports,
)
from dolphinfit.core.measure.stations import STATION_FRACTIONS

# A 4K camera (explicit values) and a dolphin lying diagonally, 600 px long, spindle-shaped
CAMERA = CameraPreset("test-4k", "", 8.8, 13.2, 3840, 2160, "test", True)
TIP_PX, LENGTH_PX, MAX_WIDTH_PX = np.array([1000.0, 800.0]), 600.0, 100.0


def _doc() -> AnnotationFile:
    """The frame-7 annotation of the diagonal dolphin, at 18 m by barometer."""
    axis = np.array([0.8, 0.6])
    normal = np.array([-axis[1], axis[0]])
    centres = TIP_PX + STATION_FRACTIONS[:, None] * LENGTH_PX * axis
    half = MAX_WIDTH_PX / 2 * np.sin(np.pi * STATION_FRACTIONS)[:, None]
    edges = np.stack([centres + half * normal, centres - half * normal], axis=1)
    midline = np.stack([TIP_PX, TIP_PX + LENGTH_PX * axis])
    return AnnotationFile(Annotation(7, midline, edges),
                          Calibration(CAMERA, None, 18.0, "barometer"),
                          media_path="clip.mp4", notes="calm sea")


def _estimate(num_draws: int = 0):
    source = measured_image_from_annotation(_doc(), image_id="D7", notes=["by hand"])
    errors = default_error_model(source.altitude_source, source.is_camera_approximate)
    estimate = estimate_baseline(source.pixels, source.focal_px, source.record.altitude_m,
                                 BaselineSettings(hw=load_hw_preset()), errors, num_draws,
                                 np.random.default_rng(3))
    return source, estimate


def test_measured_image_carries_calibration_and_notes():
    """Pixels from the clicks; export metadata and Xcertainty fields from the calibration."""
    source, _ = _estimate()
    assert source.pixels.length_px == pytest.approx(LENGTH_PX, rel=1e-9)
    assert source.pixels.widths_px[9] == pytest.approx(MAX_WIDTH_PX * np.sin(np.pi / 2))
    assert source.focal_px == pytest.approx(8.8 / 13.2 * 3840, rel=1e-12)
    assert (source.record.image_id, source.record.image_path, source.record.notes) == \
        ("D7", "clip.mp4", "calm sea")
    assert (source.image_width_px, source.sensor_width_mm, source.uas) == (3840, 13.2, "")
    assert source.notes[0].startswith("frame 7, camera explicit") and source.notes[1] == "by hand"


def test_result_record_holds_the_estimate_and_its_provenance():
    """The record's volume is estimate_baseline's; input, seed and calibration are recorded."""
    source, estimate = _estimate(num_draws=20)
    result = result_record(source, estimate, input_name="D7", seed=3)
    assert result["volume_m3"] == float(estimate.point.volume_m3)
    assert (result["schema_version"], result["input"], result["seed"]) == \
        (RESULT_SCHEMA_VERSION, "D7", 3)
    assert (result["altitude_m"], result["altitude_source"]) == (18.0, "barometer")
    assert result["uncertainty"]["num_draws"] == 20
    json.dumps(result)  # JSON-ready


def test_default_error_model_takes_overrides():
    """Defaults by altitude source; named fields replaced."""
    errors = default_error_model("laser", False, digitisation_sd_px=0.0)
    assert errors.digitisation_sd_px == 0.0
    assert errors.altitude_sd_fraction < default_error_model("manual", False).altitude_sd_fraction


def _read_row(path):
    with open(path, newline="", encoding="utf-8") as file:
        (row,) = list(csv.DictReader(file))
    return row


def test_write_exports_writes_four_files_that_read_back(tmp_path):
    """STEM_measure.json, STEM_mmx.csv, STEM_wide.csv and STEM_collatrix.csv; the MorphoMetriX
    file and the wide row give back the pixels; the rows are wide_csv_row's and
    collatrix_csv_row's, both keyed on the image's name and the MorphoMetriX file."""
    source, estimate = _estimate()
    result = result_record(source, estimate, input_name="D7", seed=0)
    paths = write_exports(tmp_path / "d7", source, estimate, result)
    assert [p.name for p in paths] == ["d7_measure.json", "d7_mmx.csv", "d7_wide.csv",
                                       "d7_collatrix.csv"]
    assert json.loads(paths[0].read_text(encoding="utf-8"))["stations"] == result["stations"]
    record = read_morphometrix(paths[1])
    assert record.lengths_px["TL"] == pytest.approx(LENGTH_PX, rel=1e-9)
    np.testing.assert_allclose([record.widths_px["TL"][pct] for pct in (5.0, 50.0, 95.0)],
                               source.pixels.widths_px[[0, 9, 18]], rtol=1e-9)
    row = _read_row(paths[2])
    assert row == wide_csv_row(source, estimate, result, csv_name="d7_mmx.csv")
    assert float(row["TL_w05.00_px"]) == pytest.approx(source.pixels.widths_px[0], rel=1e-9)
    assert (row["csv"], row["Image"], row["Baro_Alt"], row["Iw"]) == \
        ("d7_mmx.csv", "clip.mp4", "18", "3840")
    assert float(row["volume_m3"]) == pytest.approx(result["volume_m3"], rel=1e-9)
    collatrix = _read_row(paths[3])
    assert collatrix == collatrix_csv_row(source, estimate, csv_name="d7_mmx.csv")
    assert (collatrix["csv"], collatrix["Image"], collatrix["Image_ID"]) == \
        ("d7_mmx.csv", "clip.mp4", "D7")
    assert float(collatrix["TL"]) == pytest.approx(result["length_m"], rel=1e-9)


def test_collatrix_row_fills_skipped_stations_as_the_volume_does():
    """Stations 15 % and 55 % skipped: CollatriX gets the interpolated widths the volume used
    (it cannot skip a station), listed in Filled_Widths; measured ones are as measured."""
    source, estimate = _estimate()
    widths = source.pixels.widths_px.copy()
    widths[[2, 10]] = np.nan
    skipped = estimate_baseline(replace(source.pixels, widths_px=widths), source.focal_px,
                                18.0, BaselineSettings(hw=load_hw_preset()),
                                estimate.errors, 0, np.random.default_rng(0))
    row = collatrix_csv_row(source, skipped, csv_name="x.csv", image_id="D7 dolphin 2")
    stations = skipped.to_json()["stations"]
    assert float(row["TL_w15.00"]) == pytest.approx(stations[2]["width_m"], rel=1e-9)
    assert float(row["TL_w55.00"]) == pytest.approx(stations[10]["width_m"], rel=1e-9)
    assert float(row["TL_w50.00"]) == pytest.approx(widths[9] * skipped.m_per_px, rel=1e-9)
    assert (row["Filled_Widths"], row["Image_ID"]) == ("15 55", "D7 dolphin 2")


def test_mass_model_from_json(tmp_path):
    """Known keys override the paper's constants; an unknown key raises naming the file."""
    path = tmp_path / "mass.json"
    path.write_text(json.dumps({"density_intercept_kg_m3": 1030.0}), encoding="utf-8")
    assert mass_model_from_json(path).density_intercept_kg_m3 == 1030.0
    path.write_text(json.dumps({"density": 1030.0}), encoding="utf-8")
    with pytest.raises(InputError, match="mass.json: expected an object with keys among"):
        mass_model_from_json(path)
