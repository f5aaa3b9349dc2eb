"""Tests for core/io/altitude_csv.py: frame- and time-keyed altitude tables."""

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_csv import read_altitude_csv, write_altitude_csv


def _csv(tmp_path, text: str):
    path = tmp_path / "altitude.csv"
    path.write_text(text)
    return path


def test_frame_keyed_with_missing_cells_and_extra_columns(tmp_path):
    """frame,altitude_m rows read exactly; empty and NaN cells are missing; extras ignored."""
    samples = read_altitude_csv(_csv(tmp_path, "frame,altitude_m,note\n0,20.5,a\n3,,b\n"
                                               "7,NaN,c\n12,21.25,d\n"))
    assert samples.frame_idx.tolist() == [0, 3, 7, 12] and samples.time_s is None
    np.testing.assert_array_equal(samples.altitude_m, [20.5, np.nan, np.nan, 21.25])
    assert (samples.source.kind, samples.source.field) == ("csv", "altitude_m")


def test_time_keyed_and_frame_preferred(tmp_path):
    """time_s,altitude_m rows are keyed by time; with both keys, frame wins."""
    samples = read_altitude_csv(_csv(tmp_path, "time_s,altitude_m\n0.0,19\n0.5,19.5\n"))
    assert samples.time_s.tolist() == [0.0, 0.5] and samples.altitude_m.tolist() == [19, 19.5]
    both = read_altitude_csv(_csv(tmp_path, "time_s,frame,altitude_m\n0.0,0,19\n0.5,15,19.5\n"))
    assert both.frame_idx.tolist() == [0, 15]


def test_round_trip_through_the_writer(tmp_path):
    """Written columns read back equal, NaN as an empty cell, floats trimmed."""
    path = tmp_path / "out.csv"
    write_altitude_csv(path, {"time_s": np.array([0.0, 0.02, 0.04]),
                              "altitude_m": np.array([-0.9 + 0.0, np.nan, 20.1 + 1.5])})
    assert path.read_text().splitlines() == ["time_s,altitude_m", "0,-0.9", "0.02,", "0.04,21.6"]
    samples = read_altitude_csv(path)
    np.testing.assert_array_equal(samples.altitude_m, [-0.9, np.nan, 21.6])


@pytest.mark.parametrize("text, problem", [
    ("", "empty"),
    ("frame,altitude_m\n", "no rows"),
    ("frame;altitude_m\n0;20\n", "line 1: expected columns"),
    ("frame,altitude_m\n0,20\n0,21\n", "line 3: frame 0 is not greater"),
    ("time_s,altitude_m\n0.0,20\n0.1,high\n", "line 3: altitude_m 'high' is not a number"),
    ("frame,altitude_m\n1.5,20\n", "line 2: frame '1.5' is not a valid frame index"),
    ("frame,altitude_m\n0\n", "line 2: 1 cells"),
], ids=["empty", "header-only", "semicolons", "repeated-frame", "not-a-number",
        "fractional-frame", "short-row"])
def test_bad_tables_raise_naming_file_and_line(tmp_path, text, problem):
    """Malformed tables raise InputError naming the file, the line and the problem."""
    path = _csv(tmp_path, text)
    with pytest.raises(InputError, match=problem) as info:
        read_altitude_csv(path)
    assert str(path) in str(info.value)
