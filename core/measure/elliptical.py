"""The elliptical volume baseline (Christiansen et al. 2019) on arrays of station widths.

Plain numpy functions. Shapes: S = 19 stations at 5 %, 10 %, … 95 % of body length BL; ``...``
any batch (e.g. D Monte Carlo draws). Units: metres in, m³ out; HW ratios are height / width.

Volume (DESIGN.md §7, reference/morphometrics.md §2.1): 20 segments of Δx = 0.05·BL between
stations 0 %, 5 %, … 100 %, with w = h = 0 at both ends. Width and height vary linearly along a
segment and cross-sections are ellipses of axes w and h, so the exact segment volume is
π·Δx/24·(2·w1·h1 + w1·h2 + w2·h1 + 2·w2·h2).

Tail (a visible choice, morphometrics.md §2.2): "measured" uses the 90 % and 95 % widths;
"extrapolated" (CollatriX, the paper, after Christiansen 2019) ignores them and tapers linearly
from 85 % to zero at 100 %: w90 = ⅔·w85, w95 = ⅓·w85, and likewise for heights.
"""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.measure.condition import BodyCondition, MassModel, body_condition
from dolphinfit.core.measure.stations import STATION_FRACTIONS

SEGMENT_FRACTION = 0.05  # Δx / BL: 20 segments (DESIGN §7)
TAIL_MEASURED = "measured"
TAIL_EXTRAPOLATED = "extrapolated"
TAIL_OPTIONS = (TAIL_EXTRAPOLATED, TAIL_MEASURED)
TAIL_SOURCE_IDX = 16            # the 85 % station
TAIL_IDX = (17, 18)             # the 90 % and 95 % stations
TAIL_FACTORS = (2.0 / 3.0, 1.0 / 3.0)  # CollatriX bv_ellipse: w90 = ⅔·w85, w95 = ⅓·w85

# Body area index range: 20–70 % of BL (Burnett et al. 2018 for gray whales, as used by
# Bierlich et al. 2021b; secondary, morphometrics.md §2.3). The range is a user choice.
BAI_RANGE = (0.20, 0.70)


def apply_tail(values: np.ndarray, tail: str) -> np.ndarray:
    """(..., S) station values with the tail option applied (a copy).

    ``tail`` = "measured" keeps them; "extrapolated" sets the 90 % and 95 % values to ⅔ and ⅓
    of the 85 % value. Works for widths and heights alike.
    """
    if tail not in TAIL_OPTIONS:
        raise ValueError(f"tail must be one of {TAIL_OPTIONS}, got {tail!r}")
    values = np.array(values, dtype=np.float64)
    if tail == TAIL_EXTRAPOLATED:
        for idx, factor in zip(TAIL_IDX, TAIL_FACTORS):
            values[..., idx] = factor * values[..., TAIL_SOURCE_IDX]
    return values


def used_stations(tail: str) -> np.ndarray:
    """(S,) bool: the stations whose measured widths the volume uses under ``tail``."""
    is_used = np.ones(len(STATION_FRACTIONS), dtype=bool)
    if tail == TAIL_EXTRAPOLATED:
        is_used[list(TAIL_IDX)] = False
    return is_used


class NoWidthError(ValueError):
    """A measurement with no width the volume uses: its length alone can be shown."""


def fill_skipped(widths: np.ndarray, tail: str) -> tuple[np.ndarray, np.ndarray]:
    """Fill unmeasured (NaN) stations that the volume uses by linear interpolation.

    widths: (S,) float, NaN = not measured. Interpolates along the body between the nearest
    measured stations, those the tail option later replaces included (a measured 90 % width
    says how the body narrows after 85 %), and the zero widths at 0 % and 100 %. Returns the
    filled (S,) widths and an (S,) bool marking the stations filled. Stations the tail option
    ignores are left as they are. Raises NoWidthError when no used station is measured.
    """
    widths = np.asarray(widths, dtype=np.float64)
    is_used = used_stations(tail)
    is_known = np.isfinite(widths)
    if not (is_used & is_known).any():
        raise NoWidthError("no station width is measured")
    is_filled = is_used & ~is_known
    known_at = np.concatenate([[0.0], STATION_FRACTIONS[is_known], [1.0]])
    known_w = np.concatenate([[0.0], widths[is_known], [0.0]])
    filled = widths.copy()
    filled[is_filled] = np.interp(STATION_FRACTIONS[is_filled], known_at, known_w)
    return filled, is_filled


def _with_ends(values: np.ndarray) -> np.ndarray:
    """(..., S + 2) station values with the zero ends at 0 % and 100 % added."""
    zeros = np.zeros(values.shape[:-1] + (1,))
    return np.concatenate([zeros, values, zeros], axis=-1)


def segment_volumes(length_m: np.ndarray, widths_m: np.ndarray,
                    heights_m: np.ndarray) -> np.ndarray:
    """(..., 20) volume of each elliptical frustum, m³.

    length_m: (...) body length BL; widths_m, heights_m: (..., S) at the stations (tail
    already applied). Segment k runs between stations k and k + 1 of 0 %, 5 %, … 100 %.
    """
    w, h = _with_ends(np.asarray(widths_m)), _with_ends(np.asarray(heights_m))
    w1, w2, h1, h2 = w[..., :-1], w[..., 1:], h[..., :-1], h[..., 1:]
    dx = SEGMENT_FRACTION * np.asarray(length_m)[..., None]
    return np.pi * dx / 24.0 * (2 * w1 * h1 + w1 * h2 + w2 * h1 + 2 * w2 * h2)


def elliptical_volume(length_m: np.ndarray, widths_m: np.ndarray, hw_ratios: np.ndarray,
                      tail: str) -> np.ndarray:
    """(...) elliptical body volume, m³.

    length_m: (...); widths_m: (..., S) measured widths (no NaN among the used stations);
    hw_ratios: (..., S) or (S,) height / width per station, finite wherever the tail option
    takes heights from them. Heights are widths × HW ratio, then the tail option applies to
    both.
    """
    widths = np.asarray(widths_m, dtype=np.float64)
    heights = widths * np.asarray(hw_ratios, dtype=np.float64)
    return segment_volumes(length_m, apply_tail(widths, tail),
                           apply_tail(heights, tail)).sum(axis=-1)


def circular_volume(length_m: np.ndarray, widths_m: np.ndarray, tail: str) -> np.ndarray:
    """(...) volume with circular cross-sections (HW = 1), m³.

    Equal to the circular-frustum sum Σ π·Δx/3·(r1² + r1·r2 + r2²), r = w/2 (Christiansen et
    al. 2018), over the same 20 segments with zero ends.
    """
    widths = np.asarray(widths_m, dtype=np.float64)
    return elliptical_volume(length_m, widths, np.ones(widths.shape[-1]), tail)


BAI_METHODS = ("trapezoid", "parabola")


def _bai_stations(bai_range: tuple[float, float]) -> np.ndarray:
    """(S,) bool: the stations inside ``bai_range`` (fractions of BL, both ends included)."""
    lower, upper = bai_range
    is_in = (STATION_FRACTIONS >= lower - 1e-9) & (STATION_FRACTIONS <= upper + 1e-9)
    if is_in.sum() < 3:
        raise ValueError(f"bai_range {bai_range} holds fewer than three stations")
    return is_in


def projected_area(length_m: np.ndarray, widths_m: np.ndarray,
                   bai_range: tuple[float, float] = BAI_RANGE,
                   method: str = "trapezoid") -> np.ndarray:
    """(...) dorsal area (m²) of the body between the first and last station in ``bai_range``.

    "trapezoid": the widths joined by straight lines (Christiansen et al. 2016; CollatriX's
    ``bai_trapezoid``, Xcertainty). "parabola": a least-squares parabola through the widths
    against the position along the body, integrated over the range (Burnett et al. 2018;
    CollatriX's ``bai_parabola``); fitted over fractions of BL, so that x = BL · f and the
    area is BL times the parabola's integral over f. length_m: (...); widths_m: (..., S).
    """
    is_in = _bai_stations(bai_range)
    length = np.asarray(length_m, dtype=np.float64)
    widths = np.asarray(widths_m, dtype=np.float64)[..., is_in]
    fractions = STATION_FRACTIONS[is_in]
    if method == "trapezoid":
        steps = np.diff(fractions)
        integral = (steps * (widths[..., 1:] + widths[..., :-1]) / 2).sum(axis=-1)
    elif method == "parabola":
        flat = widths.reshape(-1, fractions.size)
        coefficients = np.polyfit(fractions, flat.T, 2)                  # (3, N)
        antiderivative = np.stack([coefficients[0] / 3, coefficients[1] / 2, coefficients[2]])
        ends = np.array([fractions[-1], fractions[0]])
        at = (antiderivative[:, :, None] * ends ** np.array([3, 2, 1])[:, None, None]).sum(0)
        integral = (at[:, 0] - at[:, 1]).reshape(widths.shape[:-1])
    else:
        raise ValueError(f"BAI method must be one of {BAI_METHODS}, got {method!r}")
    return length * integral


def body_area_index(length_m: np.ndarray, widths_m: np.ndarray,
                    bai_range: tuple[float, float] = BAI_RANGE,
                    method: str = "trapezoid") -> np.ndarray:
    """(...) body area index: ``projected_area`` / (range · BL)² × 100, the range between the
    first and last station in ``bai_range`` (CollatriX's and Xcertainty's definition)."""
    fractions = STATION_FRACTIONS[_bai_stations(bai_range)]
    span = fractions[-1] - fractions[0]
    length = np.asarray(length_m, dtype=np.float64)
    return (projected_area(length, widths_m, bai_range, method)
            / (span * length) ** 2 * 100.0)


@dataclass(frozen=True, eq=False)
class EllipticalResult:
    """The elliptical baseline for one set of inputs (or a batch of D draws).

    Arrays carry the batch shape ``...`` of the inputs: length_m (...); widths_m and
    heights_m (..., S) as used by the volume (tail applied); volumes (...) m³; bai,
    bai_parabola (...) and the dorsal areas behind them (...) m² (``projected_area``).
    """

    length_m: np.ndarray
    widths_m: np.ndarray
    heights_m: np.ndarray
    volume_m3: np.ndarray
    volume_circular_m3: np.ndarray
    bai: np.ndarray
    bai_parabola: np.ndarray
    surface_area_m2: np.ndarray
    surface_area_parabola_m2: np.ndarray
    condition: BodyCondition


def measure_elliptical(length_m: np.ndarray, widths_m: np.ndarray, hw_ratios: np.ndarray,
                       tail: str, mass_model: MassModel = MassModel(),
                       bai_range: tuple[float, float] = BAI_RANGE) -> EllipticalResult:
    """Volume, circular volume, BAI, body condition and mass from metric station widths.

    length_m: (...); widths_m: (..., S), filled where the volume needs them; hw_ratios:
    (..., S) or (S,).
    """
    widths = np.asarray(widths_m, dtype=np.float64)
    used_widths = apply_tail(widths, tail)
    volume = elliptical_volume(length_m, widths, hw_ratios, tail)
    return EllipticalResult(
        length_m=np.asarray(length_m, dtype=np.float64),
        widths_m=used_widths,
        heights_m=apply_tail(widths * hw_ratios, tail),
        volume_m3=volume,
        volume_circular_m3=circular_volume(length_m, widths, tail),
        bai=body_area_index(length_m, used_widths, bai_range),
        bai_parabola=body_area_index(length_m, used_widths, bai_range, "parabola"),
        surface_area_m2=projected_area(length_m, used_widths, bai_range),
        surface_area_parabola_m2=projected_area(length_m, used_widths, bai_range, "parabola"),
        condition=body_condition(length_m, volume, mass_model),
    )
