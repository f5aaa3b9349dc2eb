"""Freefly Astro logs (core/io/astro_log.py): the camera's laser range on the video's clock,
picked by read_altitude from its header, on a log written here in the documented columns."""

from pathlib import Path

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.astro_log import is_astro_log, read_astro_log
from dolphinfit.core.io.telemetry import read_altitude

HEADER = ("Unix Time (ms),Video Time (s),Altitude (m above takeoff location),"
          "Camera Range (m),Latitude,Longitude")
ROWS = [
    "1700000000000,,19.9,20.31,-25.7,113.7",      # not recording yet: dropped
    "1700000000500,0.00,20.0,20.42,-25.7,113.7",
    "1700000001000,0.50,20.1,0.00,-25.7,113.7",   # the range finder's error reading
    "1700000001500,1.00,20.1,20.57,-25.7,113.7",
    "1700000001600,1.00,20.1,20.58,-25.7,113.7",  # the same video time again: dropped
    "1700000002000,1.50,20.2,20.66,-25.7,113.7",
]


def _log(tmp_path: Path, rows=ROWS, header=HEADER) -> Path:
    path = tmp_path / "astro_flight.csv"
    path.write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    return path


def test_the_camera_range_on_the_video_clock(tmp_path):
    path = _log(tmp_path)
    assert is_astro_log(path)
    samples = read_astro_log(path)
    np.testing.assert_array_equal(samples.time_s, [0.0, 0.5, 1.0, 1.5])
    np.testing.assert_array_equal(samples.altitude_m[[0, 2, 3]], [20.42, 20.57, 20.66])
    assert np.isnan(samples.altitude_m[1])
    assert samples.source.kind == "laser" and samples.source.family == "freefly-astro"
    assert any("lines 2: not recording" in w for w in samples.warnings)
    assert any("lines 4: laser error reading" in w for w in samples.warnings)
    assert any("lines 6: not later" in w for w in samples.warnings)
    # read_altitude recognises it by its header (a .csv would otherwise be an altitude CSV)
    chosen = read_altitude(path, time_offset_s=0.5)
    np.testing.assert_array_equal(chosen.time_s, [-0.5, 0.0, 0.5, 1.0])
    assert chosen.source.family == "freefly-astro"


def test_a_log_without_its_columns_or_rows_is_refused(tmp_path):
    with pytest.raises(InputError, match="no Camera Range \\(m\\) column"):
        read_astro_log(_log(tmp_path, header="Unix Time (ms),Video Time (s),Altitude"))
    with pytest.raises(InputError, match="no row with a video time"):
        read_astro_log(_log(tmp_path, rows=[ROWS[0]]))
    with pytest.raises(InputError, match="line 2: Camera Range \\(m\\) 'far' is not a number"):
        read_astro_log(_log(tmp_path, rows=["1,0.0,20,far,0,0"]))
