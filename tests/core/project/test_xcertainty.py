"""The Xcertainty tables: the columns and units of Xcertainty's own examples (gw_data for
measurements, co_data for calibration objects, read from its .rda files), filled from a
project's measured frames and its altitude calibration."""

import csv
import shutil
import warnings
from dataclasses import replace
from datetime import datetime, timedelta
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import rdata

from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.project.evaluate import all_keys, frame_results
from dolphinfit.core.project.exports import export_frames
from dolphinfit.core.project.model import AltitudeSpec, MeasurementKey
from dolphinfit.core.project.results import measure_frame
from dolphinfit.core.measure.xcertainty import CALIBRATION_COLUMNS, MEASUREMENT_COLUMNS

from .conftest import write_black_clip
from .test_calibrations import calibration_set

XCERTAINTY = Path(__file__).resolve().parents[2] / "data" / "real" / "xcertainty"
SRT_DIR = Path(__file__).resolve().parents[2] / "data" / "srt"


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


def _dates(project, tmp_path) -> list[tuple[str, str, str]]:
    """(image, year, DOY) of each row of the project's Xcertainty table, as written; its
    media in ``tmp_path``, every frame measured."""
    results, skipped = frame_results(project, tmp_path / "survey.dolphinfit", all_keys(project),
                                     num_draws=0)
    assert skipped == []
    export_frames(project, results, tmp_path / "out", "survey")
    with open(tmp_path / "out" / "survey_xcertainty.csv", newline="", encoding="utf-8") as f:
        return [(row["image"], row["year"], row["DOY"]) for row in csv.DictReader(f)]


def test_a_clip_with_an_srt_is_dated_and_one_without_is_not(project, tmp_path):
    """Two clips of one survey: the one with mavic_pro.SRT beside it (legacy family, dated
    2017-08-05, day 217) gets year and DOY on each frame; the one without an SRT gets them
    empty, not 0 or NaN."""
    write_black_clip(tmp_path / "media")
    shutil.copy(tmp_path / "media" / "clip.mp4", tmp_path / "media" / "other.mp4")
    shutil.copy(SRT_DIR / "mavic_pro.SRT", tmp_path / "media" / "clip.SRT")
    undated = replace(project.clips[0], media_path="media/other.mp4")
    assert _dates(replace(project, clips=(project.clips[0], undated)), tmp_path) == [
        ("clip_f000003", "2017", "217"), ("clip_f000007", "2017", "217"),
        ("other_f000003", "", ""), ("other_f000007", "", "")]


@pytest.mark.parametrize("name, year, doy", [
    ("MAVIC3.srt", "2021", "359"),                   # modern, 2021-12-25
    ("dji-srt-2025/Mini5PRO.SRT", "2026", "147"),    # modern, 2026-05-27
    ("mavic_air2.srt", "2022", "121"),               # html-bracket, 2022-05-01
    ("mavic_2_style.SRT", "2017", "217"),            # html-bracket, no timing, 2017-08-05
    ("broken_incomplete.SRT", "2017", "184"),        # legacy, cut off, 2017-07-03
    ("p4p_sample.SRT", "", ""),                      # single-line: no dates
])
def test_every_srt_family_beside_a_clip_dates_its_frames(project, tmp_path, name, year, doy):
    """The SRT beside a clip whose altitude is typed in dates its frames."""
    write_black_clip(tmp_path / "media")
    shutil.copy(SRT_DIR / name, tmp_path / "media" / "clip.SRT")
    assert _dates(project, tmp_path) == [("clip_f000003", year, doy),
                                         ("clip_f000007", year, doy)]


def test_the_altitude_srt_dates_each_frame_across_midnight(project, tmp_path):
    """An SRT given as the clip's altitude file (not beside it) whose clock reads 23:59:59.5 on
    31 December 2023 at 0 s: frame 3 (0.3 s at 10 fps) is day 365 of 2023, frame 7 (0.7 s)
    day 1 of 2024."""
    write_black_clip(tmp_path / "media")
    start = datetime(2023, 12, 31, 23, 59, 59, 500000)
    cues = [f"{n + 1}\n00:00:00,{100 * n:03d} --> 00:00:00,{100 * n + 100:03d}\n"
            f"FrameCnt: {n + 1}, DiffTime: 100ms\n"
            f"{(start + timedelta(seconds=0.1 * n)).isoformat(' ', 'milliseconds')}\n"
            "[iso: 100] [rel_alt: 20.000 abs_alt: 30.000]\n" for n in range(8)]
    (tmp_path / "flight.SRT").write_text("\n".join(cues), encoding="utf-8")
    clip = replace(project.clips[0], altitude=AltitudeSpec(path="flight.SRT",
                                                           source="barometer"))
    assert _dates(replace(project, clips=(clip,)), tmp_path) == [
        ("clip_f000003", "2023", "365"), ("clip_f000007", "2024", "1")]


def test_an_unreadable_srt_leaves_the_date_empty_and_the_frames_measured(project, tmp_path):
    """A file beside the clip that is no DJI SRT gives no date and stops no measurement."""
    write_black_clip(tmp_path / "media")
    (tmp_path / "media" / "clip.SRT").write_text("1\n00:00:01,000 --> 00:00:02,000\nHello!\n",
                                                 encoding="utf-8")
    assert _dates(project, tmp_path) == [("clip_f000003", "", ""), ("clip_f000007", "", "")]
