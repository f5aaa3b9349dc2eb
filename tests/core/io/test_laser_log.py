"""Tests for core/io/laser_log.py on the LidarBoX-style fixture tests/data/laser/LOG_0007.CSV."""

import math
from pathlib import Path

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.laser_log import is_laser_log, read_laser_log

LOG = Path(__file__).parents[2] / "data" / "laser" / "LOG_0007.CSV"
# The fixture's dated rows, one a second from 17:02:10 (the repeated second left out).
LASER_CM = [1873, 1921, 1978, 2016, 2043, 2051, 13000, 2049, 2047, 2052, None, 2046, 2044,
            15000, 2040, 2037, 2035, 2036, 2038, 2041]
TILT_DEG = [4.85, 3.97, 2.61, 1.88, 3.52, 2.04, 2.37, 1.46, 0.92, 1.73, 2.15, 2.88, 3.31, 2.56,
            1.94, 1.27, 0.85, 1.12, 1.69, 2.23]
MISSING = {6, 10, 13}  # 13000 cm, NaN, 15000 cm


def test_tilt_corrected_altitudes_and_error_values():
    """Altitude = cm / 100 × cos(tilt); 13000, 15000 and NaN readings are missing."""
    samples = read_laser_log(LOG)
    assert samples.num_samples == 20
    for idx, (laser_cm, tilt_deg) in enumerate(zip(LASER_CM, TILT_DEG)):
        if idx in MISSING:
            assert np.isnan(samples.altitude_m[idx])
        else:
            assert samples.altitude_m[idx] == laser_cm / 100 * math.cos(math.radians(tilt_deg))
    assert samples.altitude_m[4] == pytest.approx(20.3915, abs=1e-4)


def test_time_offset_puts_rows_on_the_clip_clock():
    """Rows are 1 s apart; the clip starting 2.5 s into the log shifts them by −2.5 s."""
    samples = read_laser_log(LOG, time_offset_s=2.5)
    np.testing.assert_array_equal(samples.time_s, np.arange(20) - 2.5)
    assert samples.source.time_offset_s == 2.5 and samples.source.family == "lidarbox"
    assert not samples.source.is_relative


def test_gimballed_laser_skips_the_tilt_correction():
    """With tilt_correction off the altitude is the laser distance in metres."""
    samples = read_laser_log(LOG, tilt_correction=False)
    assert samples.altitude_m[4] == 20.43


def test_warnings_name_the_lines():
    """The row before the GPS fix, the repeated second and the bad readings are named."""
    warnings = "\n".join(read_laser_log(LOG).warnings)
    assert "lines 4: no valid date and time, dropped" in warnings
    assert "lines 21: not later than the row before, dropped" in warnings
    assert "lines 11, 18: laser error reading (13000/15000 cm)" in warnings
    assert "lines 15: no laser reading" in warnings


def test_recognised_by_header_whatever_the_suffix(tmp_path):
    """A LidarBoX log is recognised by its header; an altitude CSV is not."""
    other = tmp_path / "alt.csv"
    other.write_text("frame,altitude_m\n0,20\n")
    assert is_laser_log(LOG) and not is_laser_log(other)


def _log(tmp_path, header: str, row: str) -> Path:
    path = tmp_path / "LOG_0001.TXT"
    path.write_text(f"# logger\n#{header}\n{row}\n")
    return path


def test_missing_tilt_column_raises(tmp_path):
    """A log without tilt_deg raises InputError unless the tilt correction is off."""
    path = _log(tmp_path, "gmt_date\tgmt_time\tlaser_altitude_cm", "2019/07/14\t17:02:10\t2000")
    with pytest.raises(InputError, match="no tilt_deg column"):
        read_laser_log(path)
    assert read_laser_log(path, tilt_correction=False).altitude_m.tolist() == [20.0]


def test_bad_reading_raises_naming_the_line(tmp_path):
    """A laser cell that is not a number raises InputError naming file, line and column."""
    path = _log(tmp_path, "gmt_date\tgmt_time\tlaser_altitude_cm\ttilt_deg",
                "2019/07/14\t17:02:10\tabc\t1.0")
    with pytest.raises(InputError, match=r"line 3: laser_altitude_cm 'abc'") as info:
        read_laser_log(path)
    assert str(path) in str(info.value)


def test_no_header_raises(tmp_path):
    """A file without the laser header is not a laser log."""
    path = tmp_path / "x.txt"
    path.write_text("2019/07/14\t17:02:10\t2000\n")
    with pytest.raises(InputError, match="no '#' header"):
        read_laser_log(path)
