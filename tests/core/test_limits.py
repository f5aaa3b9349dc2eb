"""The plausible ranges and their checks: values, types and the names in the messages."""

import math
from dataclasses import dataclass

import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.limits import (
    ALTITUDE_M, BODY_LENGTH_M, at_least, body_measurements, check_fields, count, in_range,
    result_figures, time_window,
)


@pytest.mark.parametrize("value", [1.0, 20, 500.0])
def test_altitudes_in_range_pass_as_floats(value):
    assert in_range(value, ALTITUDE_M, "--altitude") == float(value)


@pytest.mark.parametrize("value, message", [
    (0.0, "--altitude: 0 m is outside the plausible range 1–500 m"),
    (1e6, "--altitude: 1e+06 m is outside"),
    (math.nan, "--altitude: expected a finite number, got nan"),
    ("20", "--altitude: expected a number, got '20'"),
    (True, "--altitude: expected a number, got True"),
])
def test_implausible_altitudes_are_refused_naming_the_option(value, message):
    with pytest.raises(InputError, match=message.replace("+", r"\+")):
        in_range(value, ALTITUDE_M, "--altitude")


def test_counts_need_whole_numbers():
    assert count(3, 1, "--threads") == 3
    for bad in (0, -1, 2.0, True):
        with pytest.raises(InputError, match="--threads"):
            count(bad, 1, "--threads")


def test_time_window_needs_start_before_end():
    time_window(0.0, 2.5, "--start", "--end")
    time_window(None, 1.0, "--start", "--end")
    with pytest.raises(InputError, match="--start 3 s is not before --end 3 s"):
        time_window(3.0, 3.0, "--start", "--end")
    with pytest.raises(InputError, match="--end: must be at least 0"):
        time_window(None, -1.0, "--start", "--end")


def test_body_measurements():
    """A 2.5 m body with 0.4 m widths passes; a width beyond the length or a 0.2 m body not."""
    body_measurements(2.5, [0.4, math.nan, 0.3], "f.csv")
    with pytest.raises(InputError, match="f.csv: width 3 m is not between 0 and the body "
                                         "length 2.5 m"):
        body_measurements(2.5, [0.4, 3.0], "f.csv")
    with pytest.raises(InputError, match="f.csv: body length: 0.2 m is outside the plausible "
                                         f"range {BODY_LENGTH_M.text()}"):
        body_measurements(0.2, [], "f.csv")


def test_result_figures_refuse_nan_and_negative_mass():
    result_figures({"length_m": 2.5, "volume_m3": 0.2, "mass_kg": 200.0}, "fit")
    with pytest.raises(InputError, match="fit: mass_kg: must be positive, got -3"):
        result_figures({"length_m": 2.5, "mass_kg": -3.0}, "fit")
    with pytest.raises(InputError, match="fit: volume_m3: expected a finite number"):
        result_figures({"volume_m3": math.nan}, "fit")


@dataclass
class _Options:
    size_m: float = 1.0
    depth_m: float | None = None
    rgb: tuple[float, float, float] = (0.1, 0.2, 0.3)
    label: str = "x"


def test_check_fields_names_the_field():
    """Every number field is finite; ranges and minimums apply by name; text is left alone."""
    check_fields(_Options(), "opt ", minimum={"size_m": 0.0})
    for options, message in ((_Options(size_m=-1.0), "opt size_m: must be at least 0"),
                             (_Options(depth_m=math.inf), "opt depth_m: expected a finite"),
                             (_Options(rgb=(0.1, math.nan, 0.3)), "opt rgb: expected a finite"),
                             (_Options(size_m="big"), "opt size_m: expected a number")):
        with pytest.raises(InputError, match=message):
            check_fields(options, "opt ", minimum={"size_m": 0.0})
    assert at_least(0, 0.0, "x") == 0.0
