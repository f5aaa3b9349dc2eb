"""Elliptical volume, tail options, circular variant and BAI against analytic solids."""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from dolphinfit.core.measure.morphometrix import pixel_measurements, read_morphometrix
from dolphinfit.core.measure.elliptical import (
    TAIL_EXTRAPOLATED, TAIL_MEASURED, apply_tail, body_area_index, circular_volume,
    projected_area,
    elliptical_volume, fill_skipped, segment_volumes,
)
from dolphinfit.core.measure.stations import STATION_FRACTIONS, STATION_PCT

BL_M = 2.5
WIDTH_M = 0.4
DX_M = 0.05 * BL_M
# Provisional template widths / BL at 5 … 95 % (reference/morphometrics.md §4)
TEMPLATE_W_BL = np.array([.045, .085, .13, .15, .165, .175, .18, .18, .175, .16, .14, .125,
                          .11, .09, .075, .06, .045, .030, .015])
PROVISIONAL_HW = np.repeat([1.0, 1.125, 1.4, 1.625, 2.4, np.nan], [3, 5, 3, 4, 2, 2])
# A real MorphoMetriX v1 file (CollatriX's demo whale): TL 24.09 m, widths every 10 %
MMX_V1 = Path(__file__).resolve().parents[2] / "data" / "morphometrix" / \
    "mmx_v1_Whale1_170816_A_F2_DSC04215.csv"


def test_cylinder_is_two_end_cones_and_18_cylinders():
    """Constant width, HW = 1, measured tail: V = (14/3)·π·w²·Δx to rounding (§2.4)."""
    widths = np.full(19, WIDTH_M)
    volume = elliptical_volume(BL_M, widths, np.ones(19), TAIL_MEASURED)
    assert volume == pytest.approx(14 / 3 * math.pi * WIDTH_M**2 * DX_M, rel=1e-13)
    assert volume == pytest.approx(0.2333 * math.pi * WIDTH_M**2 * BL_M, rel=2e-4)


def test_cylinder_with_the_extrapolated_tail_tapers_from_85_percent():
    """Extrapolated tail: 16 cylinders, a cone over 85–100 % and the rostrum cone."""
    widths = np.full(19, WIDTH_M)
    widths[-2:] = np.nan  # ignored under this option
    volume = elliptical_volume(BL_M, widths, np.ones(19), TAIL_EXTRAPOLATED)
    exact = math.pi / 4 * WIDTH_M**2 * (16 * DX_M + 3 * DX_M / 3 + DX_M / 3)
    assert volume == pytest.approx(exact, rel=1e-13)


def test_elliptic_cone_is_exact():
    """w = W·p, HW = 1.5: a cone to 95 % plus a cap cone to 100 %, ⅓·(π/4)·w·h·BL in all."""
    widths = WIDTH_M * STATION_FRACTIONS
    volume = elliptical_volume(BL_M, widths, np.full(19, 1.5), TAIL_MEASURED)
    base_w = 0.95 * WIDTH_M
    assert volume == pytest.approx(math.pi / 12 * base_w * 1.5 * base_w * BL_M, rel=1e-13)


def _piecewise_linear_volume(widths, hw):
    """∫ (π/4)·w(x)·h(x) dx with w, h linear between stations, by adaptive quadrature."""
    at = np.concatenate([[0.0], STATION_FRACTIONS, [1.0]]) * BL_M
    w = np.concatenate([[0.0], widths, [0.0]])
    h = np.concatenate([[0.0], widths * hw, [0.0]])
    return sum(quad(lambda x: math.pi / 4 * np.interp(x, at, w) * np.interp(x, at, h), a, b)[0]
               for a, b in zip(at[:-1], at[1:]))


def test_ellipsoid_closed_form_and_its_discretisation_error():
    """Ellipsoid (W, 1.3·W): the closed form equals the integral of the sampled body, which
    lies 0.87 % under the analytic (π/6)·BL·W·H (linear segments cut into a convex outline)."""
    widths = WIDTH_M * np.sqrt(4 * STATION_FRACTIONS * (1 - STATION_FRACTIONS))
    hw = np.full(19, 1.3)
    volume = elliptical_volume(BL_M, widths, hw, TAIL_MEASURED)
    assert volume == pytest.approx(_piecewise_linear_volume(widths, hw), rel=1e-10)
    analytic = math.pi / 6 * BL_M * WIDTH_M * 1.3 * WIDTH_M
    assert volume / analytic - 1 == pytest.approx(-0.00866, abs=5e-5)


def test_circular_variant_is_the_circular_frustum_sum():
    """HW = 1 equals Σ π·Δx/3·(r1² + r1·r2 + r2²) with zero ends (Christiansen 2018)."""
    widths = TEMPLATE_W_BL * BL_M
    r = np.concatenate([[0.0], widths, [0.0]]) / 2
    frustums = np.sum(math.pi * DX_M / 3 * (r[:-1] ** 2 + r[:-1] * r[1:] + r[1:] ** 2))
    assert circular_volume(BL_M, widths, TAIL_MEASURED) == pytest.approx(frustums, rel=1e-13)


def test_provisional_template_volumes_match_the_reference():
    """§4 widths, CollatriX tail: V/BL³ = 0.0148 with the default HW row, 0.0115 circular."""
    widths = TEMPLATE_W_BL * BL_M
    elliptical = elliptical_volume(BL_M, widths, PROVISIONAL_HW, TAIL_EXTRAPOLATED)
    assert elliptical / BL_M**3 == pytest.approx(0.0148, abs=5e-5)
    assert circular_volume(BL_M, widths, TAIL_EXTRAPOLATED) / BL_M**3 == \
        pytest.approx(0.0115, abs=5e-5)


def test_tail_option_sets_two_thirds_and_one_third_of_85_percent():
    """Extrapolated: w90 = ⅔·w85 and w95 = ⅓·w85; measured leaves the values alone."""
    values = np.arange(1.0, 20.0)
    tail = apply_tail(values, TAIL_EXTRAPOLATED)
    assert tail[17] == pytest.approx(17 * 2 / 3) and tail[18] == pytest.approx(17 / 3)
    np.testing.assert_array_equal(apply_tail(values, TAIL_MEASURED), values)
    with pytest.raises(ValueError, match="tail must be one of"):
        apply_tail(values, "cut")


def test_segment_volumes_are_batched():
    """(D, S) widths give (D, 20) segments; each row equals its own unbatched result."""
    widths = np.stack([TEMPLATE_W_BL, 2 * TEMPLATE_W_BL]) * BL_M
    lengths = np.array([BL_M, 2 * BL_M])
    batch = segment_volumes(lengths, widths, widths)
    assert batch.shape == (2, 20)
    np.testing.assert_allclose(batch[1], segment_volumes(2 * BL_M, widths[1], widths[1]))
    assert batch[1].sum() == pytest.approx(8 * batch[0].sum())  # every size doubled


def test_fill_skipped_interpolates_along_the_body():
    """A skipped station gets the mean of its neighbours; an end station tapers to zero."""
    widths = TEMPLATE_W_BL.copy()
    widths[[0, 6]] = np.nan
    filled, is_filled = fill_skipped(widths, TAIL_MEASURED)
    assert filled[6] == pytest.approx((0.175 + 0.18) / 2)
    assert filled[0] == pytest.approx(0.085 / 2)
    assert is_filled.tolist() == [i in (0, 6) for i in range(19)]


def test_fill_skipped_ignores_the_tail_the_option_replaces():
    """Under the extrapolated tail, unmeasured 90/95 % stations are not filled or flagged."""
    widths = TEMPLATE_W_BL.copy()
    widths[-2:] = np.nan
    filled, is_filled = fill_skipped(widths, TAIL_EXTRAPOLATED)
    assert not is_filled.any() and np.isnan(filled[-2:]).all()


def test_fill_takes_the_measured_tail_widths_before_the_tail_rule():
    """Real v1 file, extrapolated tail: the missing 85 % width is the mean of the measured 80 %
    and 90 % widths (0.680 m), not ¾ of the 80 % one that interpolating to the zero at 100 %
    gave (0.705 m, 3.7 % wide). Through ⅔ and ⅓ of it at 90 % and 95 %, the old fill
    overstated the volume by 0.115 % with the provisional HW row (0.059 % circular)."""
    record = read_morphometrix(MMX_V1)
    pixels = pixel_measurements(record, MMX_V1)
    length, widths = pixels.length_px * record.m_per_px, pixels.widths_px * record.m_per_px
    filled, is_filled = fill_skipped(widths, TAIL_EXTRAPOLATED)
    assert filled[16] == pytest.approx((0.94 + 0.42) / 2, rel=1e-9)
    assert is_filled.tolist() == [i % 2 == 0 and i < 17 for i in range(19)]
    np.testing.assert_allclose(filled[:17], fill_skipped(widths, TAIL_MEASURED)[0][:17])
    to_zero = filled.copy()
    to_zero[16] = 0.75 * widths[15]
    volume = elliptical_volume(length, filled, PROVISIONAL_HW, TAIL_EXTRAPOLATED)
    assert volume == pytest.approx(106.3098, abs=1e-4)
    old = elliptical_volume(length, to_zero, PROVISIONAL_HW, TAIL_EXTRAPOLATED)
    assert 100 * (volume / old - 1) == pytest.approx(-0.1152, abs=1e-4)
    circular = [circular_volume(length, w, TAIL_EXTRAPOLATED) for w in (filled, to_zero)]
    assert 100 * (circular[0] / circular[1] - 1) == pytest.approx(-0.0594, abs=1e-4)


def test_body_area_index_of_a_constant_width():
    """Constant width over 20–70 %: area w·0.5·BL, BAI = w·0.5·BL / (0.5·BL)² × 100."""
    widths = np.full(19, WIDTH_M)
    assert body_area_index(BL_M, widths) == pytest.approx(200 * WIDTH_M / BL_M, rel=1e-12)
    assert body_area_index(BL_M, widths, (0.05, 0.95)) == pytest.approx(
        100 * WIDTH_M / (0.9 * BL_M), rel=1e-12)


def _collatrix_bai(length_m: float, widths_m: np.ndarray, lower_pct: int, upper_pct: int,
                   interval_pct: int = 5) -> tuple[float, float, float, float]:
    """CollatriX's bodycondition_functions, written out as its documentation and code state
    them: (BAI and surface area by parabola, BAI and surface area by trapezoid). The parabola
    is a least-squares quadratic of the widths against x = BL · percent / 100, integrated over
    [BL · lower, BL · upper] with scipy's quad; the trapezoid sums ½ (w + W) h, h = BL ·
    interval; both BAIs are the area / (BL · range)² × 100."""
    pcts = np.arange(lower_pct, upper_pct + interval_pct, interval_pct)
    w = widths_m[np.searchsorted(np.round(STATION_FRACTIONS * 100), pcts)]
    x = length_m * pcts / 100
    fit = np.poly1d(np.polyfit(x, w, 2))
    sa_parabola = quad(fit, length_m * lower_pct / 100, length_m * upper_pct / 100)[0]
    sa_trapezoid = sum(0.5 * (a + b) * length_m * interval_pct / 100
                       for a, b in zip(w[:-1], w[1:]))
    scale = (length_m * (upper_pct - lower_pct) / 100) ** 2 / 100
    return sa_parabola / scale, sa_parabola, sa_trapezoid / scale, sa_trapezoid


@pytest.mark.parametrize("lower, upper", [(20, 70), (5, 95), (25, 80)])
def test_body_area_index_agrees_with_collatrix_by_parabola_and_trapezoid(lower, upper):
    """On a real body's widths (the minke measured by hand at 19 stations) and on random ones,
    both BAIs and both surface areas agree with CollatriX's formulas to 1e-6 (relative)."""
    record = read_morphometrix(Path(__file__).resolve().parents[2] / "data" / "real"
                               / "minke" / "demo-annotated.csv")
    real = (record.lengths_m["Total_Length"], np.array([record.widths_m["Total_Length"][pct]
                                              for pct in STATION_PCT.tolist()]))
    rng = np.random.default_rng(4)
    for length, widths in (real, (2.4, rng.uniform(0.1, 0.5, 19))):
        bai_par, sa_par, bai_trap, sa_trap = _collatrix_bai(length, widths, lower, upper)
        span = (lower / 100, upper / 100)
        assert body_area_index(length, widths, span, "parabola") == pytest.approx(bai_par,
                                                                                 rel=1e-6)
        assert projected_area(length, widths, span, "parabola") == pytest.approx(sa_par,
                                                                                rel=1e-6)
        assert body_area_index(length, widths, span) == pytest.approx(bai_trap, rel=1e-6)
        assert projected_area(length, widths, span) == pytest.approx(sa_trap, rel=1e-6)
