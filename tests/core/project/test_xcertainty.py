"""The Xcertainty tables: the columns and units of Xcertainty's own examples (gw_data for
measurements, co_data for calibration objects, read from its .rda files), filled from a
project's measured frames and its altitude calibration."""

import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import rdata

from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.project.exports import export_frames
from dolphinfit.core.project.model import AltitudeSpec, MeasurementKey
from dolphinfit.core.project.results import measure_frame
from dolphinfit.core.measure.xcertainty import CALIBRATION_COLUMNS, MEASUREMENT_COLUMNS

from .test_calibrations import calibration_set

XCERTAINTY = Path(__file__).resolve().parents[2] / "data" / "real" / "xcertainty"


def _example(name: str) -> pd.DataFrame:
    with warnings.catch_warnings():   # rdata reads a tibble as the data frame it is
        warnings.simplefilter("ignore", UserWarning)
        (frame,) = rdata.read_rda(XCERTAINTY / f"{name}.rda").values()
    return frame


def test_the_columns_are_xcertaintys_own_in_its_order():
    assert list(MEASUREMENT_COLUMNS) == [str(c) for c in _example("gw_data").columns]
    assert list(CALIBRATION_COLUMNS) == [str(c) for c in _example("co_data").columns]


def test_a_calibrated_barometer_project_exports_both_tables(project, camera, tmp_path):
    """Pixels as measured and altitudes as recorded (barometer: raw + launch height), the
    calibration's shots as training objects; every numeric column reads back as numbers where
    Xcertainty's examples hold numbers."""
    clip = replace(project.clips[0], altitude=AltitudeSpec(constant_m=18.0, launch_height_m=1.5,
                                                           source="barometer"),
                   altitude_calibration="test drone barometer")
    calibrated = replace(project, clips=(clip,), calibrations=(calibration_set(camera),))
    keys = (MeasurementKey(0, 0, 0), MeasurementKey(0, 0, 1))
    results = [measure_frame(calibrated, key, 18.0, "barometer", load_hw_preset(), 0)
               for key in keys]
    export_frames(calibrated, results, tmp_path, "survey")
    table = pd.read_csv(tmp_path / "survey_xcertainty.csv")
    gw = _example("gw_data")
    assert list(table.columns) == [str(c) for c in gw.columns]
    row = table.iloc[0]
    assert (row["whale_ID"], row["image"], row["uas"], row["CO.ID"]) == \
        ("clip dolphin 1", "clip_f000003", "test drone barometer", "test drone barometer")
    assert (row["Baro_Alt"], row["Launch_Ht"], row["Baro_raw"]) == (18.0, 1.5, 16.5)
    assert np.isnan(row["Laser_Alt"]) and np.isnan(row["year"])
    assert (row["Focal_Length"], row["Sw"], row["Iw"]) == (12.29, 17.27, 1280)
    measured = results[0].estimate.measured
    assert row["TL_px"] == pytest.approx(measured.length_px, rel=1e-9)
    assert row["TL_w50.00_px"] == pytest.approx(measured.widths_px[9], rel=1e-9)
    for column in gw.columns:
        if pd.api.types.is_numeric_dtype(gw[column]):
            assert pd.api.types.is_numeric_dtype(table[str(column)]), column
    shots = pd.read_csv(tmp_path / "survey_xcertainty_calibration.csv")
    co = _example("co_data")
    assert list(shots.columns) == [str(c) for c in co.columns] and len(shots) == 12
    assert (shots["CO.L"] == 2.0).all() and shots["Laser_Alt"].isna().all()
    first = calibration_set(camera).shots[0]
    assert (shots["Baro_Alt"][0], shots["Lpix"][0]) == pytest.approx(
        (first.recorded_altitude_m, first.pixel_length))


def test_each_animal_is_one_whale_id_across_the_project(project):
    """Three clips each with its "dolphin 1": three animals to Xcertainty, each after its
    clip's name; an animal a person named (a catalogue ID) in two clips is one."""
    from dolphinfit.core.project.xcertainty import subject_id

    clips = [replace(project.clips[0], media_path=f"day1/DJI_00{n}.MP4") for n in (41, 42, 43)]
    assert [subject_id(clip, "dolphin 1") for clip in clips] == \
        ["DJI_0041 dolphin 1", "DJI_0042 dolphin 1", "DJI_0043 dolphin 1"]
    assert {subject_id(clip, "Tt-0042") for clip in clips} == {"Tt-0042"}
