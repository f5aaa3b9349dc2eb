"""Tests for core/io/telemetry.py: choosing the reader, the SRT sidecar, alignment to frames."""

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_samples import AltitudeSamples, AltitudeSource
from dolphinfit.core.io.telemetry import (
    align_to_frames,
    find_srt_sidecar,
    load_telemetry,
    read_altitude,
    summarize_samples,
)
from dolphinfit.core.io.video import Clip

DATA = Path(__file__).parents[2] / "data"
SRT_DIR = DATA / "srt"
LASER_LOG = DATA / "laser" / "LOG_0007.CSV"
LAUNCH_HEIGHT_M = 1.5


def _clip(fps: float, num_frames: int, path: Path = Path("clip.mp4")) -> Clip:
    return Clip(path, fps, num_frames, 3840, 2160)


def _frame_samples(frames, altitudes) -> AltitudeSamples:
    return AltitudeSamples(np.array(altitudes, float), AltitudeSource("csv", Path("a.csv")),
                           frame_idx=np.array(frames))


def test_mavic3_frames_take_their_cue_exactly():
    """A 50 fps clip over MAVIC3.srt: every frame sits on its cue and takes rel_alt + launch."""
    telemetry = load_telemetry(_clip(50.0, 12318), SRT_DIR / "MAVIC3.srt", LAUNCH_HEIGHT_M)
    assert not telemetry.is_interpolated[6393:].any()
    assert telemetry.altitude_m[6647] == 11.1 + LAUNCH_HEIGHT_M
    assert telemetry.altitude_m[12317] == 3.6 + LAUNCH_HEIGHT_M
    assert telemetry.source.describe() == \
        "srt MAVIC3.srt (modern), rel_alt + launch height 1.50 m"


def test_altitudes_below_one_metre_are_missing_with_a_warning():
    """MAVIC3.srt's first 6393 cues (rel_alt −4.9…−0.5 m + 1.5 m: the drone below the water)
    are refused as altitudes: those frames are missing (the last one takes the next cue's
    value, one interval away), and a warning says why."""
    telemetry = load_telemetry(_clip(50.0, 12318), SRT_DIR / "MAVIC3.srt", LAUNCH_HEIGHT_M)
    assert telemetry.is_missing.tolist() == [True] * 6392 + [False] * (12318 - 6392)
    assert "6393 of 12318 altitudes outside the plausible 1–500 m taken as missing: " \
           "-0.9 m at 0 s, -0.9 m at 0.02 s" in telemetry.warnings[0]
    assert "(is the launch height missing?)" in telemetry.warnings[0]


def test_a_frame_whose_own_sample_is_impossible_is_flagged_though_bridged():
    """A 0-m row: the frame takes its neighbours' altitude, flagged as impossible (the fit
    leaves it out); the frames at good samples are not."""
    telemetry = align_to_frames(_frame_samples(range(5), [20.0, 20.2, 0.0, 20.6, 20.8]),
                                _clip(10.0, 5))
    assert telemetry.altitude_m[2] == pytest.approx(20.4)
    assert telemetry.is_impossible.tolist() == [False, False, True, False, False]
    assert "1 of 5 altitudes outside the plausible 1–500 m taken as missing: 0 m at frame 2" \
        in telemetry.warnings[0]


def test_one_hertz_legacy_srt_interpolates_between_seconds():
    """mavic_pro.SRT (from 1 s) at 30 fps: the first second holds cue 1, others interpolate."""
    telemetry = load_telemetry(_clip(30.0, 300), SRT_DIR / "mavic_pro.SRT", LAUNCH_HEIGHT_M)
    assert not telemetry.is_missing.any()
    assert np.all(telemetry.altitude_m[:30] == 1.9 + LAUNCH_HEIGHT_M)
    assert telemetry.is_interpolated[:30].all()
    assert telemetry.altitude_m[30] == 1.9 + LAUNCH_HEIGHT_M and not telemetry.is_interpolated[30]
    assert telemetry.altitude_m[75] == pytest.approx((2.0 + 1.9) / 2 + LAUNCH_HEIGHT_M)
    assert telemetry.is_interpolated[75]


def test_frames_past_the_samples_and_across_long_gaps_are_missing():
    """Frame-keyed samples: gaps up to max_gap_s interpolate; longer gaps and the tail beyond
    one sample interval are missing (NaN) and warned about."""
    samples = _frame_samples([0, 2, 3, 8, 9], [20.0, 21.0, np.nan, 24.0, 25.0])
    clip = _clip(25.0, 14)
    telemetry = align_to_frames(samples, clip)
    np.testing.assert_array_equal(telemetry.altitude_m[:11],
                                  [20, 20.5, 21, 21.5, 22, 22.5, 23, 23.5, 24, 25, 25])
    np.testing.assert_array_equal(telemetry.is_interpolated,
                                  [0, 1, 0, 1, 1, 1, 1, 1, 0, 0, 1, 0, 0, 0])
    np.testing.assert_array_equal(telemetry.is_missing, [0] * 11 + [1, 1, 1])
    strict = align_to_frames(samples, clip, max_gap_s=0.2)
    assert strict.is_missing[3:8].all() and np.isnan(strict.altitude_m[3:8]).all()
    assert "no altitude for 8 of 14 frames" in strict.warnings[-1]
    assert "frames 3–7, 11–13" in strict.warnings[-1]


def test_constant_altitude():
    """A number (or a numeric string) is the altitude of every frame."""
    telemetry = load_telemetry(_clip(25.0, 4), "20.5")
    assert telemetry.altitude_m.tolist() == [20.5] * 4 and telemetry.source.kind == "constant"
    assert load_telemetry(_clip(25.0, 2), 18).altitude_m.tolist() == [18.0, 18.0]
    for bad in (-3.0, 0.0, 1e6, float("nan")):
        with pytest.raises(InputError, match="altitude"):
            load_telemetry(_clip(25.0, 2), bad)


def test_sidecar_srt_is_found_beside_the_clip(tmp_path):
    """DJI_0001.MP4 finds DJI_0001.SRT beside it and takes its altitude."""
    clip_path = tmp_path / "DJI_0001.MP4"
    clip_path.touch()
    assert find_srt_sidecar(clip_path) is None
    with pytest.raises(InputError, match="no DJI_0001.SRT beside"):
        load_telemetry(_clip(1.0, 5, clip_path))
    shutil.copy(SRT_DIR / "p4p_sample.SRT", tmp_path / "DJI_0001.SRT")
    assert find_srt_sidecar(clip_path) == tmp_path / "DJI_0001.SRT"
    telemetry = load_telemetry(_clip(1.0, 5, clip_path), launch_height_m=LAUNCH_HEIGHT_M)
    assert telemetry.altitude_m.tolist() == [45.6 + LAUNCH_HEIGHT_M] * 5


def test_reader_chosen_by_file(tmp_path):
    """.SRT → SRT, a LidarBoX log named .CSV → laser, a .csv table → CSV, else InputError."""
    table = tmp_path / "alt.csv"
    table.write_text("time_s,altitude_m\n0,20\n")
    assert read_altitude(SRT_DIR / "p4p_sample.SRT").source.kind == "srt"
    assert read_altitude(LASER_LOG).source.kind == "laser"
    assert read_altitude(table).source.kind == "csv"
    unknown = tmp_path / "alt.xyz"
    unknown.write_text("20\n")
    with pytest.raises(InputError, match="unknown altitude file type"):
        read_altitude(unknown)
    with pytest.raises(InputError, match="no such file"):
        read_altitude(tmp_path / "missing.SRT")


def test_options_that_do_not_apply_are_warned():
    """A launch height on a laser log and a time offset on an SRT are ignored, with a warning."""
    laser = read_altitude(LASER_LOG, launch_height_m=1.5)
    assert "launch height ignored" in laser.warnings[-1]
    srt = read_altitude(SRT_DIR / "mavic_air2.srt", time_offset_s=3.0)
    assert "time offset ignored" in srt.warnings[-1]


def test_laser_log_aligned_by_time_offset():
    """A 10 fps clip that starts 2 s into the laser log takes row 2 at frame 0 and bridges the
    13000 cm error reading at log time 6 s (frame 40)."""
    telemetry = load_telemetry(_clip(10.0, 50), LASER_LOG, time_offset_s=2.0)
    laser = read_altitude(LASER_LOG)
    assert telemetry.altitude_m[0] == laser.altitude_m[2]
    assert telemetry.altitude_m[30] == laser.altitude_m[5]
    assert telemetry.altitude_m[40] == pytest.approx(
        (laser.altitude_m[5] + laser.altitude_m[7]) / 2)


def test_summary_of_the_laser_log():
    """20 rows at 1 Hz, 17 valid, three 2 s gaps around the error readings."""
    summary = summarize_samples(read_altitude(LASER_LOG))
    assert (summary.num_samples, summary.num_valid, summary.rate_hz) == (20, 17, 1.0)
    assert (summary.start_s, summary.end_s) == (0.0, 19.0)
    assert summary.gaps == ((5.0, 2.0), (9.0, 2.0), (12.0, 2.0))
    assert summary.min_altitude_m == 1873 / 100 * math.cos(math.radians(4.85))
