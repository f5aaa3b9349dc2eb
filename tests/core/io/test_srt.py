"""Tests for core/io/srt.py on every file in tests/data/srt/ (real DJI sidecars) and on small
cues written from the family descriptions in reference/ecosystem.md §7."""

import dataclasses
from datetime import datetime
from pathlib import Path

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_samples import AltitudeSamples, AltitudeSource
from dolphinfit.core.io.srt import SrtCue, SrtFile, parse_srt, read_srt, srt_clock_start

SRT_DIR = Path(__file__).parents[2] / "data" / "srt"
LAUNCH_HEIGHT_M = 1.5
ALL_FILES = sorted(p.name for p in SRT_DIR.iterdir() if p.suffix.lower() == ".srt")


def _cue(srt: SrtFile, number: int) -> SrtCue:
    return next(c for c in srt.cues if c.number == number)


def _sample(samples: AltitudeSamples, time_s: float) -> float:
    (idx,) = np.flatnonzero(samples.time_s == time_s)
    return samples.altitude_m[idx]


def test_every_shared_file_is_covered():
    """The six real files of tests/data/srt/ are the ones these tests read."""
    assert ALL_FILES == ["MAVIC3.srt", "broken_incomplete.SRT", "mavic_2_style.SRT",
                         "mavic_air2.srt", "mavic_pro.SRT", "p4p_sample.SRT"]


def test_mavic3_modern_rel_alt_plus_launch_height():
    """MAVIC3.srt: modern family, 12318 cues at 50 Hz, rel_alt + launch height per cue."""
    srt = parse_srt(SRT_DIR / "MAVIC3.srt")
    assert srt.family.name == "modern" and len(srt.cues) == 12318
    assert (_cue(srt, 1).fields["rel_alt"], _cue(srt, 1).fields["abs_alt"]) == (-2.4, 0.401)
    assert (_cue(srt, 5000).start_s, _cue(srt, 5000).fields["abs_alt"]) == (99.98, -2.099)
    assert _cue(srt, 6648).fields["abs_alt"] == 13.901
    samples = read_srt(SRT_DIR / "MAVIC3.srt", LAUNCH_HEIGHT_M)
    assert samples.source == AltitudeSource("srt", SRT_DIR / "MAVIC3.srt", "modern", "rel_alt",
                                            True, LAUNCH_HEIGHT_M)
    assert samples.num_samples == 12318
    assert _sample(samples, 0.0) == -2.4 + LAUNCH_HEIGHT_M
    assert _sample(samples, 99.98) == -4.9 + LAUNCH_HEIGHT_M
    assert _sample(samples, 132.94) == 11.1 + LAUNCH_HEIGHT_M
    assert _sample(samples, 246.34) == 3.6 + LAUNCH_HEIGHT_M
    assert samples.time_s[-1] == 246.34
    assert np.all(np.diff(samples.time_s) > 0)


def test_mavic_air2_html_bracket_absolute_altitude():
    """mavic_air2.srt: html-bracket family, absolute altitude used as is (no launch height)."""
    samples = read_srt(SRT_DIR / "mavic_air2.srt", LAUNCH_HEIGHT_M)
    assert (samples.source.family, samples.source.field) == ("html-bracket", "altitude")
    assert not samples.source.is_relative and samples.source.launch_height_m == 0.0
    assert samples.num_samples == 25
    assert (_sample(samples, 0.0), _sample(samples, 0.133), _sample(samples, 0.4)) == \
        (27.3, 28.8, 29.2)
    srt = parse_srt(SRT_DIR / "mavic_air2.srt")
    assert _cue(srt, 9).fields["SrtCnt"] == 9 and _cue(srt, 9).fields["fnum"] == 280
    assert _cue(srt, 1).timestamp.isoformat() == "2022-05-01T15:01:58.531000"


def test_mavic_pro_legacy_barometer():
    """mavic_pro.SRT: legacy family at 1 Hz from 1 s, BAROMETER + launch height."""
    samples = read_srt(SRT_DIR / "mavic_pro.SRT", LAUNCH_HEIGHT_M)
    assert (samples.source.family, samples.source.field) == ("legacy", "BAROMETER")
    assert samples.num_samples == 468 and samples.time_s[0] == 1.0
    assert _sample(samples, 1.0) == 1.9 + LAUNCH_HEIGHT_M
    assert _sample(samples, 100.0) == 72.8 + LAUNCH_HEIGHT_M
    assert _sample(samples, 468.0) == 0.0 + LAUNCH_HEIGHT_M
    assert _cue(parse_srt(SRT_DIR / "mavic_pro.SRT"), 100).fields["Fnum"] == 2.2


def test_p4p_single_line_h():
    """p4p_sample.SRT: single-line family, H (height above home) and D fields per cue."""
    srt = parse_srt(SRT_DIR / "p4p_sample.SRT")
    assert srt.family.name == "single-line" and len(srt.cues) == 5
    cue = _cue(srt, 3)
    assert (cue.start_s, cue.end_s, cue.fields["H"], cue.fields["D"], cue.fields["H.S"]) == \
        (2.0, 3.0, 45.6, 48.08, 1.9)
    samples = read_srt(SRT_DIR / "p4p_sample.SRT", LAUNCH_HEIGHT_M)
    assert samples.time_s.tolist() == [0.0, 1.0, 2.0, 3.0, 4.0]
    assert np.all(samples.altitude_m == 45.6 + LAUNCH_HEIGHT_M)


def test_mavic_2_style_has_no_timing_and_no_altitude():
    """mavic_2_style.SRT: bracket variant without timing lines or altitude: NaN, warned."""
    srt = parse_srt(SRT_DIR / "mavic_2_style.SRT")
    assert srt.family.name == "html-bracket" and len(srt.cues) == 468
    cue = _cue(srt, 400)
    assert (cue.fields["latitude"], cue.fields["longtitude"]) == (-20.2533, 149.0247)
    assert cue.start_s is None and cue.timestamp.isoformat() == "2017-08-05T14:18:31.393000"
    samples = read_srt(SRT_DIR / "mavic_2_style.SRT")
    assert samples.num_samples == 468 and np.isnan(samples.altitude_m).all()
    assert samples.time_s[399] == 399.0
    assert any("no cue carries an altitude" in w for w in samples.warnings)
    assert any("no timing lines" in w for w in samples.warnings)


def test_broken_file_warns_about_the_truncated_cue():
    """broken_incomplete.SRT: cues 1–19 read; cue 20, cut off, is NaN with a warning."""
    samples = read_srt(SRT_DIR / "broken_incomplete.SRT")
    assert samples.source.family == "legacy" and samples.num_samples == 20
    assert (_sample(samples, 1.0), _sample(samples, 19.0)) == (20.1, 7.7)
    assert np.isnan(_sample(samples, 20.0))
    assert any("no BAROMETER in cue 20 (line 115)" in w for w in samples.warnings)


@pytest.mark.parametrize("name", ALL_FILES)
def test_focal_len_is_never_a_focal_length(name):
    """No parsed cue keeps focal_len, and no parsed type has a focal-length field."""
    srt = parse_srt(SRT_DIR / name)
    assert all("focal_len" not in cue.fields for cue in srt.cues)
    for cls in (SrtFile, SrtCue, AltitudeSamples, AltitudeSource):
        assert not any("focal" in f.name for f in dataclasses.fields(cls))


M300 = """1
00:00:58,000 --> 00:00:59,000
2022.06.21 16:07:15
GPS(36.6153,-6.1130,0.0M) BAROMETER:83.3M

2
00:00:59,000 --> 00:00:60,000
2022.06.21 16:07:16
GPS(36.6153,-6.1130,0.0M) BAROMETER:83.8M

3
00:01:00,000 --> 00:01:01,000
2022.06.21 16:07:17
GPS(36.6154,-6.1132,0.0M) BAROMETER:84.0M
"""

LEGACY_HB = """1
00:00:01,000 --> 00:00:02,000
HOME(8.5412,47.3769) 2016.05.02 09:41:07
GPS(8.5410,47.3770,12) Hb:23.4 Hs:1.2
ISO:100 TV:500 EV:0 IR:2.8

2
00:00:02,000 --> 00:00:03,000
HOME(8.5412,47.3769) 2016.05.02 09:41:08
GPS(8.5410,47.3771,12) Hb:23.9 Hs:1.1
ISO:100 TV:500 EV:0 IR:2.8
"""

MINI_TRUNCATED = """1
00:00:00,000 --> 00:00:01,000
F/2.8, SS 30.15, ISO 260, EV -1.7, GPS (8.2090, 47.4692, 18), D 221.21m, H 200.70m, H.S 2.10m/s, V.S 0.00m/s

2
00:00:01,000 --> 00:00:02,000
F/2.8, SS 30.15, ISO 260, EV -1.7, GPS (8.2091, 47.4692, 18), D 222.01m, H

3

4
"""


def _write(tmp_path, name: str, text: str, encoding: str = "utf-8") -> Path:
    path = tmp_path / name
    path.write_bytes(text.encode(encoding))
    return path


def test_m300_barometer_with_a_60_second_timing_line(tmp_path):
    """Matrice 300 cues (BAROMETER:…M, lat/lon order) parse; "00:00:60,000" means 60 s."""
    srt = parse_srt(_write(tmp_path, "m300.SRT", M300))
    assert srt.family.name == "m300"
    assert [c.end_s for c in srt.cues] == [59.0, 60.0, 61.0]
    samples = read_srt(srt.path, LAUNCH_HEIGHT_M)
    assert samples.altitude_m.tolist() == [83.3 + 1.5, 83.8 + 1.5, 84.0 + 1.5]


def test_legacy_hb_variant_with_bom_and_crlf(tmp_path):
    """The older legacy variant (Hb:, TV, IR) reads with a UTF-8 BOM and CRLF line ends."""
    path = _write(tmp_path, "old.srt", "\ufeff" + LEGACY_HB.replace("\n", "\r\n"))
    samples = read_srt(path)
    assert (samples.source.family, samples.source.field) == ("legacy", "Hb")
    assert samples.altitude_m.tolist() == [23.4, 23.9] and samples.time_s.tolist() == [1.0, 2.0]


def test_utf16_file_reads(tmp_path):
    """A UTF-16 file with a byte-order mark reads like its UTF-8 twin."""
    samples = read_srt(_write(tmp_path, "m300_utf16.SRT", M300, "utf-16"))
    assert samples.altitude_m.tolist() == [83.3, 83.8, 84.0]


def test_truncated_and_empty_cues_warn(tmp_path):
    """A cue cut off before H gives NaN; empty cues 3 and 4 are dropped; both warned."""
    samples = read_srt(_write(tmp_path, "mini.SRT", MINI_TRUNCATED), LAUNCH_HEIGHT_M)
    assert samples.source.family == "single-line"
    assert samples.altitude_m[0] == 200.7 + LAUNCH_HEIGHT_M and np.isnan(samples.altitude_m[1])
    assert samples.time_s.tolist() == [0.0, 1.0]
    assert any("empty cue 3 (line 9), cue 4 (line 11) dropped" in w for w in samples.warnings)
    assert any("no H in cue 2 (line 5)" in w for w in samples.warnings)


def test_relative_altitude_without_launch_height_warns(tmp_path):
    """A relative family read without a launch height says so."""
    samples = read_srt(_write(tmp_path, "m300.SRT", M300))
    assert any("no launch height" in w for w in samples.warnings)


@pytest.mark.parametrize("text, problem", [
    ("", "empty"),
    ("just some notes\nwithout cues\n", "no subtitle cues"),
    ("1\n00:00:01,000 --> 00:00:02,000\nHello there!\n", "none carries DJI telemetry"),
], ids=["empty", "no-cues", "movie-subtitle"])
def test_not_a_dji_srt_raises(tmp_path, text, problem):
    """Empty files, text without cues and ordinary subtitles raise InputError naming the file."""
    path = _write(tmp_path, "clip.SRT", text)
    with pytest.raises(InputError, match=problem) as info:
        parse_srt(path)
    assert str(path) in str(info.value)


def test_missing_file_raises(tmp_path):
    """A missing file raises InputError naming it."""
    with pytest.raises(InputError, match="no such file"):
        parse_srt(tmp_path / "nope.SRT")


@pytest.mark.parametrize("name, start", [
    ("MAVIC3.srt", datetime(2021, 12, 25, 12, 27, 52, 371000)),   # modern, 50 Hz
    ("dji-srt-2025/Mini5PRO.SRT", datetime(2026, 5, 27, 13, 14, 22, 911000)),   # modern
    ("dji-srt-2025/air3S.SRT", datetime(2026, 5, 17, 8, 28, 30, 219000)),   # modern
    ("mavic_air2.srt", datetime(2022, 5, 1, 15, 1, 58, 532000)),   # html-bracket, "…,531,716"
    ("mavic_2_style.SRT", datetime(2017, 8, 5, 14, 11, 51, 393000)),   # no timing lines
    ("mavic_pro.SRT", datetime(2017, 8, 5, 14, 11, 50)),   # legacy: its first cue is at 1 s
    ("broken_incomplete.SRT", datetime(2017, 7, 3, 10, 15, 2)),   # legacy, cut off
    ("p4p_sample.SRT", None),   # single-line: no date lines
])
def test_clock_start_is_the_date_line_at_the_videos_time_0(name, start):
    """The camera's local date-time at 0 s of every real file: the first cue's date line less
    its cue time (MAVIC3: the median over 12318 cues, 2 ms before the first date line)."""
    assert srt_clock_start(parse_srt(SRT_DIR / name)) == start


@pytest.mark.parametrize("text, start", [
    (M300, datetime(2022, 6, 21, 16, 6, 17)),   # first cue at 58 s, dated 16:07:15
    (LEGACY_HB, datetime(2016, 5, 2, 9, 41, 6)),   # "YYYY.MM.DD" after HOME(…)
], ids=["m300", "legacy-hb"])
def test_clock_start_of_the_families_without_a_sample_file(tmp_path, text, start):
    """The Matrice 300 and the older legacy variant date their cues the same way."""
    assert srt_clock_start(parse_srt(_write(tmp_path, "x.SRT", text))) == start
