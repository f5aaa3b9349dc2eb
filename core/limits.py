"""Plausible ranges of every physical input, decided once, and the checks that apply them.

Each boundary (CLI options, altitude files, MorphoMetriX and annotation files, configuration
files, mass-model overrides) checks its values here and refuses, with an InputError naming the
option, file or field, what no drone survey of a dolphin can produce. The ranges are wide on
purpose: they catch typos, unit mix-ups and corrupt files, not unusual flights.
"""

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from numbers import Integral, Real
from typing import get_args

from dolphinfit.core.errors import InputError


@dataclass(frozen=True)
class Limits:
    """A closed range [low, high] in ``unit`` and why it is plausible."""

    low: float
    high: float
    unit: str

    def text(self, value: float | None = None) -> str:
        """"1–500 m", or ``value`` with the unit ("0.2 m")."""
        number = f"{self.low:g}–{self.high:g}" if value is None else f"{value:g}"
        return f"{number} {self.unit}" if self.unit else number


# DESIGN.md §1 flies at 15–25 m; 1 m is a drone on the water, 500 m twice the legal ceiling.
ALTITUDE_M = Limits(1.0, 500.0, "m")
# The smallest newborn delphinid to the largest blue whale (rostrum tip to fluke notch).
BODY_LENGTH_M = Limits(0.5, 35.0, "m")
# Take-off point above the water: a beach or deck to a cliff top; slightly below (a boat's
# deck lower than the pier it set off from) is possible.
LAUNCH_HEIGHT_M = Limits(-10.0, 500.0, "m")
# Real focal lengths of drone and survey cameras (DJI Mini 4.5 mm … long lenses).
FOCAL_MM = Limits(1.0, 1000.0, "mm")
# Sensor widths: 1/3.2" phone-class sensors (4.5 mm) to medium format (54 mm).
SENSOR_WIDTH_MM = Limits(1.0, 100.0, "mm")
# Pixel pitch (sensor width / image width): 0.5 µm to 0.1 mm.
PIXEL_DIMENSION_MM = Limits(0.0005, 0.1, "mm/px")
IMAGE_SIZE_PX = Limits(16, 100_000, "px")
FPS = Limits(0.01, 1000.0, "frames/s")
# How far the masks' outline may lie off the animal's, one SD: exact masks to a fifth of a
# dolphin's width on a 1080p frame at 25 m.
MASK_OUTLINE_SD_PX = Limits(0.0, 5.0, "px")
# Mass model (Baieri et al.): density of a dolphin's body and the BCI range a relation may be
# trusted on; a body twice or none of its expected volume is beyond any condition.
DENSITY_KG_M3 = Limits(800.0, 1300.0, "kg/m³")
BCI = Limits(-1.0, 1.0, "")


def number(value: object, where: str) -> float:
    """``value`` as a float if it is a finite real number (no bool, no text); InputError
    naming ``where`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise InputError(f"{where}: expected a number, got {value!r}")
    if not math.isfinite(value):
        raise InputError(f"{where}: expected a finite number, got {value!r}")
    return float(value)


def in_range(value: object, limits: Limits, where: str) -> float:
    """``value`` as a float if it is a finite number inside ``limits``; InputError naming
    ``where``, the value and the range otherwise."""
    checked = number(value, where)
    if not limits.low <= checked <= limits.high:
        raise InputError(f"{where}: {limits.text(checked)} is outside the plausible range "
                         f"{limits.text()}")
    return checked


def at_least(value: object, minimum: float, where: str) -> float:
    """``value`` as a float if it is a finite number ≥ ``minimum``; InputError otherwise."""
    checked = number(value, where)
    if checked < minimum:
        raise InputError(f"{where}: must be at least {minimum:g}, got {checked:g}")
    return checked


def positive(value: object, where: str) -> float:
    """``value`` as a float if it is a finite number > 0; InputError otherwise."""
    checked = number(value, where)
    if not checked > 0:
        raise InputError(f"{where}: must be positive, got {checked:g}")
    return checked


def one_of(value: object, choices: tuple[str, ...], where: str) -> None:
    """InputError unless ``value`` is one of ``choices``."""
    if value not in choices:
        raise InputError(f"{where}: one of {', '.join(choices)}, got {value!r}")


def count(value: object, minimum: int, where: str) -> int:
    """``value`` as an int if it is a whole number (no bool) ≥ ``minimum``; InputError
    otherwise."""
    if isinstance(value, bool) or not isinstance(value, Integral):
        raise InputError(f"{where}: expected a whole number, got {value!r}")
    if value < minimum:
        raise InputError(f"{where}: must be at least {minimum}, got {value}")
    return int(value)


def time_window(start_s: float | None, end_s: float | None, start_where: str,
                end_where: str) -> None:
    """InputError unless each given bound is a finite time ≥ 0 and start is before end."""
    for value, where in ((start_s, start_where), (end_s, end_where)):
        if value is not None:
            at_least(value, 0.0, where)
    if start_s is not None and end_s is not None and not start_s < end_s:
        raise InputError(f"{start_where} {start_s:g} s is not before {end_where} {end_s:g} s")


def body_measurements(length_m: float, widths_m: list[float], where: str) -> None:
    """InputError unless the body length is plausible and every measured width (NaN: not
    measured) is positive and shorter than the body."""
    in_range(length_m, BODY_LENGTH_M, f"{where}: body length")
    too_wide = [w for w in widths_m if math.isfinite(w) and not 0 < w < length_m]
    if too_wide:
        raise InputError(f"{where}: width {too_wide[0]:.4g} m is not between 0 and the body "
                         f"length {length_m:.4g} m")


def result_figures(figures: dict[str, float], where: str) -> None:
    """InputError unless a result's length is plausible and its volume and mass positive
    numbers: such a result is never written as a success."""
    for name, value in figures.items():
        if name == "length_m":
            in_range(value, BODY_LENGTH_M, f"{where}: {name}")
        else:
            positive(value, f"{where}: {name}")


def check_fields(instance: object, where: str, ranges: Mapping[str, Limits] | None = None,
                 minimum: Mapping[str, float] | None = None) -> None:
    """InputError naming the field (after the prefix ``where``, e.g. "fit option ") unless
    every number field of a dataclass instance (``int``, ``float``, ``float | None``, tuples of
    them, by annotation) holds finite numbers,
    those in ``ranges`` lie in their range and those in ``minimum`` are at least that. Nested
    dataclasses check themselves."""
    for field in fields(instance):
        value, at = getattr(instance, field.name), f"{where}{field.name}"
        if value is None or not (field.type in (int, float) or
                                 {int, float} & set(get_args(field.type))):
            continue
        for item in value if isinstance(value, tuple) else (value,):
            number(item, at)
        if field.name in (ranges or {}):
            in_range(value, ranges[field.name], at)
        if field.name in (minimum or {}):
            at_least(value, minimum[field.name], at)
