"""`dolphinfit telemetry` driven through app.cli.main on the real SRT files and the laser log."""

from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.app.cli import main

DATA = Path(__file__).parents[1] / "data"


def _clip(path: Path, num_frames: int, fps: float) -> Path:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), fps, (64, 48))
    for _ in range(num_frames):
        writer.write(np.full((48, 64, 3), 90, np.uint8))
    writer.release()
    return path


def test_srt_summary_and_per_sample_csv(tmp_path, capsys):
    """MAVIC3.srt: family, rate, range with launch height; CSV with one row per cue."""
    out = tmp_path / "alt.csv"
    assert main(["telemetry", str(DATA / "srt" / "MAVIC3.srt"), "--launch-height", "1.5",
                 "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "DJI SRT, modern family (Mavic 3" in text
    assert "rel_alt (relative to take-off) + launch height 1.50 m" in text
    assert "12318, 12318 with altitude, 0–246.34 s, 50 Hz" in text
    assert "-3.80 … 12.70 m" in text
    rows = out.read_text().splitlines()
    assert (rows[0], rows[1], rows[-1], len(rows)) == ("time_s,altitude_m", "0,-0.9",
                                                       "246.34,5.1", 12319)


def test_laser_log_per_frame_csv(tmp_path, capsys):
    """The laser log aligned to a 10-frame clip at 10 fps: one CSV row per frame."""
    clip = _clip(tmp_path / "clip.avi", 10, 10.0)
    out = tmp_path / "frames.csv"
    assert main(["telemetry", str(DATA / "laser" / "LOG_0007.CSV"), "--time-offset", "3",
                 "--clip", str(clip), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "laser log (LidarBoX)" in text and "gaps       3:" in text
    assert "frames     10: 0 missing, 9 interpolated" in text
    rows = out.read_text().splitlines()
    assert rows[0] == "frame,time_s,altitude_m,is_interpolated" and len(rows) == 11
    assert rows[1] == f"0,0,{2016 / 100 * np.cos(np.radians(1.88)):.6f},0"


def test_a_filmed_gps_clock_gives_the_time_offset(tmp_path, capsys):
    """The log starts at 17:02:10 UTC; a clock filmed at frame 30 of a 10 fps clip (3.0 s in)
    reads 17:02:31.5, so the clip began 18.5 s into the log: the same altitudes as
    --time-offset 18.5. Without --clip, with both options or a bad reading: exit 2."""
    clip = _clip(tmp_path / "clip.avi", 40, 10.0)
    log = str(DATA / "laser" / "LOG_0007.CSV")
    by_clock, by_offset = tmp_path / "clock.csv", tmp_path / "offset.csv"
    assert main(["telemetry", log, "--clip", str(clip), "--gps-clock",
                 "2019/07/14 17:02:31.5", "30", "--out", str(by_clock)]) == 0
    assert "time offset 18.500 s" in capsys.readouterr().out
    assert main(["telemetry", log, "--clip", str(clip), "--time-offset", "18.5",
                 "--out", str(by_offset)]) == 0
    assert by_clock.read_text() == by_offset.read_text()
    for argv, why in ((["--gps-clock", "2019/07/14 17:02:31", "3"], "needs --clip"),
                      (["--clip", str(clip), "--time-offset", "2", "--gps-clock",
                        "2019/07/14 17:02:31", "3"], "not both"),
                      (["--clip", str(clip), "--gps-clock", "17:02:31", "3"],
                       "expected a UTC date and time"),
                      (["--clip", str(clip), "--gps-clock", "2019/07/14 17:02:31", "400"],
                       "has 40 frames"),
                      (["--clip", str(clip), "--gps-clock", "2019/07/16 17:02:31", "3"],
                       "more than a day")):
        assert main(["telemetry", log, *argv]) == 2
        assert why in capsys.readouterr().err


def test_srt_without_altitude_reports_none(capsys):
    """The Mavic 2 Pro-style file has no altitude: said plainly, exit 0."""
    assert main(["telemetry", str(DATA / "srt" / "mavic_2_style.SRT")]) == 0
    text = capsys.readouterr().out
    assert "altitude   none" in text and "no cue carries an altitude" in text


@pytest.mark.parametrize("name, text, problem", [
    ("frames.csv", "frame,altitude_m\n0,20\n", "keyed by frame; give --clip"),
    ("alt.csv", "frame;altitude\n", "expected columns"),
    ("missing.SRT", None, "no such file"),
])
def test_bad_input_exits_2(tmp_path, capsys, name, text, problem):
    """Bad altitude files exit with code 2 and a message naming the file."""
    path = tmp_path / name
    if text is not None:
        path.write_text(text)
    assert main(["telemetry", str(path)]) == 2
    err = capsys.readouterr().err
    assert problem in err and str(path) in err


def test_a_freefly_astro_log_is_named_as_one(tmp_path, capsys):
    """An Astro log's camera range is a laser source, named by its logger (not LidarBoX)."""
    path = tmp_path / "astro_flight.csv"
    path.write_text("Unix Time (ms),Video Time (s),Altitude (m above takeoff location),"
                    "Camera Range (m),Latitude,Longitude\n"
                    "1700000000500,0.00,20.0,20.42,-25.7,113.7\n"
                    "1700000001500,1.00,20.1,20.57,-25.7,113.7\n", encoding="utf-8")
    assert main(["telemetry", str(path)]) == 0
    text = capsys.readouterr().out
    assert "laser log (Freefly Astro)" in text and "LidarBoX" not in text
