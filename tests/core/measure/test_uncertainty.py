"""Monte Carlo uncertainty: collapse without error, exact scalings, and interval coverage."""

import threading

import numpy as np
import pytest
from scipy.optimize import brentq

from dolphinfit.core.measure.annotation import (
    Annotation, PixelMeasurements, pixel_measurements, place_stations,
)
from dolphinfit.core.measure.baseline import BaselineSettings, estimate_baseline
from dolphinfit.core.measure.condition import body_condition
from dolphinfit.core.measure.elliptical import TAIL_EXTRAPOLATED, elliptical_volume
from dolphinfit.core.measure.hw_ratios import HWRatios, load_hw_preset
from dolphinfit.core.measure.stations import STATION_FRACTIONS
from dolphinfit.core.measure.uncertainty import BATCH_DRAWS, ErrorModel, draw_pixels, monte_carlo
from dolphinfit.core.progress import Cancelled

# Provisional template widths / BL (reference/morphometrics.md §4)
W_BL = np.array([.045, .085, .13, .15, .165, .175, .18, .18, .175, .16, .14, .125, .11, .09,
                 .075, .06, .045, .030, .015])
BL_M, ALTITUDE_M = 2.5, 20.0
FOCAL_PX = 12.29 / 17.27 * 3840  # DJI Mavic 3 at 4K UHD: 2732.7 px
M_PER_PX = ALTITUDE_M / FOCAL_PX
NO_ERROR = ErrorModel(0.0, 0.0, 0.0, 0.0)
HW = load_hw_preset()


def _pixels(widths_bl=W_BL, is_mirrored=False):
    """The 2.5 m template seen from 20 m: 341.6 px long."""
    return PixelMeasurements(BL_M / M_PER_PX, widths_bl * BL_M / M_PER_PX, is_mirrored)


def _draw(errors, num_draws=4000, seed=0, pixels=None, hw=HW):
    return monte_carlo(pixels or _pixels(), FOCAL_PX, ALTITUDE_M, hw, TAIL_EXTRAPOLATED,
                       errors, num_draws, np.random.default_rng(seed))


def test_zero_error_collapses_the_interval_onto_the_value():
    """With every SD zero, mean = low = high = the nominal value and SD = 0."""
    estimate = estimate_baseline(_pixels(), FOCAL_PX, ALTITUDE_M, BaselineSettings(HW),
                                 NO_ERROR, 50, np.random.default_rng(0))
    for name, value in (("length_m", estimate.point.length_m),
                        ("volume_m3", estimate.point.volume_m3),
                        ("bci", estimate.point.condition.bci),
                        ("mass_kg", estimate.point.condition.mass_kg)):
        summary = getattr(estimate.interval, name)
        assert float(summary.sd) == pytest.approx(0.0, abs=1e-12)
        for bound in (summary.mean, summary.low, summary.high):
            assert float(bound) == pytest.approx(float(value), rel=1e-12)
    np.testing.assert_allclose(estimate.interval.widths_m.high, estimate.point.widths_m,
                               rtol=1e-12)


def test_same_seed_same_draws():
    """Draws come only from the generator passed in: equal seeds, equal results."""
    errors = ErrorModel.default("barometer", False)
    first, again, other = _draw(errors, 200, 3), _draw(errors, 200, 3), _draw(errors, 200, 4)
    assert float(first.volume_m3.sd) == float(again.volume_m3.sd)
    assert float(first.volume_m3.sd) != float(other.volume_m3.sd)


def test_progress_and_cancel_between_batches_leave_the_draws_alone():
    """Progress rises to every draw of the estimate (budget included); with it the numbers are
    the same, and a cancel stops the Monte Carlo."""
    errors = ErrorModel.default("barometer", False)
    num_draws = 2 * BATCH_DRAWS + 10

    def estimate(**kwargs):
        return estimate_baseline(_pixels(), FOCAL_PX, ALTITUDE_M, BaselineSettings(HW), errors,
                                 num_draws, np.random.default_rng(2), **kwargs)

    reports = []
    plain, watched = estimate(), estimate(progress=reports.append)
    for name in ("length_m", "volume_m3", "mass_kg", "widths_m"):
        np.testing.assert_array_equal(getattr(watched.interval, name).sd,
                                      getattr(plain.interval, name).sd)
    assert watched.budget["camera"].bci.sd == plain.budget["camera"].bci.sd
    steps = [r.step for r in reports]
    assert steps == sorted(steps) and steps[-1] == 5 * num_draws
    assert {r.total for r in reports} == {5 * num_draws} and len(reports) == 5 * 3
    cancel = threading.Event()
    cancel.set()
    with pytest.raises(Cancelled):
        estimate(cancel=cancel)


def test_altitude_error_scales_length_by_one_and_volume_by_three():
    """Laser 1 %: length SD 1 % (L ∝ h) and volume SD 3 % (V ∝ h³), within the 2 % sampling
    error of an SD from 4000 draws (1/√(2·4000) = 1.1 %)."""
    result = _draw(ErrorModel(0.01, 0.0, 0.0, 0.0))
    assert float(result.length_m.sd) / BL_M == pytest.approx(0.01, rel=0.03)
    assert float(result.volume_m3.sd / result.volume_m3.mean) == pytest.approx(0.03, rel=0.03)


def test_digitisation_error_of_length_and_of_a_mirrored_width():
    """σ = 2 px: length SD √2·σ (two end clicks); at a station with no taper, a width's SD is
    √2·σ from two edges, 2·σ when one side is doubled."""
    flat = np.full(19, 0.15)
    for is_mirrored, factor in ((False, np.sqrt(2)), (True, 2.0)):
        length_px, widths_px = draw_pixels(_pixels(flat, is_mirrored), 2.0, 8000,
                                           np.random.default_rng(1))
        assert length_px.std() == pytest.approx(np.sqrt(2) * 2.0, rel=0.03)
        assert widths_px[:, 9].std() == pytest.approx(factor * 2.0, rel=0.03)


def test_digitisation_moves_stations_along_a_taper():
    """Where the body tapers, station shifts add |dw/dx|·σ_shift to the width error: at 5 %
    (taper 0.85, shift SD σ·√(0.95² + 0.05²)) the SD is √(2σ² + (0.85·0.951·σ)²)."""
    _, widths_px = draw_pixels(_pixels(), 2.0, 8000, np.random.default_rng(2))
    taper = W_BL[1] / 0.10  # central difference from the zero width at 0 %
    expected = 2.0 * np.sqrt(2 + (taper * np.hypot(0.95, 0.05)) ** 2)
    assert widths_px[:, 0].std() == pytest.approx(expected, rel=0.03)


def test_hw_error_is_shared_by_all_stations():
    """A 10 % SD on every ratio moves the volume by 10 % (one shared draw), not by the ~3 %
    that independent station errors would average to."""
    ratios = np.full(19, 1.3)
    hw = HWRatios("test", ratios, 0.1 * ratios, "test", False)
    result = _draw(ErrorModel(0.0, 0.0, 0.0, 1.0), hw=hw)
    assert float(result.volume_m3.sd / result.volume_m3.mean) == pytest.approx(0.10, rel=0.03)


def test_budget_sources_add_up_in_quadrature():
    """Each source alone, squared and summed, gives the total variance within 10 %."""
    estimate = estimate_baseline(_pixels(), FOCAL_PX, ALTITUDE_M, BaselineSettings(HW),
                                 ErrorModel.default("barometer", True), 4000,
                                 np.random.default_rng(5))
    parts = sum(float(r.volume_m3.sd) ** 2 for r in estimate.budget.values())
    assert parts == pytest.approx(float(estimate.interval.volume_m3.sd) ** 2, rel=0.10)
    assert set(estimate.budget) == {"altitude", "camera", "digitisation", "hw_ratios"}


# --- coverage on synthetic annotations --------------------------------------------------------

CLICK_SD_PX, LASER_SD, FOCAL_SD = 2.0, 0.01, 0.005
COVERAGE_REPEATS, COVERAGE_DRAWS = 400, 400
ORIGIN_PX = np.array([100.0, 300.0])


def _outline_half_width(u_px):
    """True half width (px) of the straight test animal at image column u."""
    at = np.concatenate([[0.0], STATION_FRACTIONS, [1.0]])
    widths = np.concatenate([[0.0], W_BL, [0.0]]) * BL_M / M_PER_PX
    return np.interp((u_px - ORIGIN_PX[0]) / (BL_M / M_PER_PX), at, widths) / 2


def _clicked_edge(point, normal, sign):
    """Where the perpendicular through ``point`` crosses the true outline on one side."""
    side = np.sign(sign * normal[1])

    def beyond_outline(r):
        """Signed distance past the outline of the point r px out along the perpendicular."""
        u, v = point + sign * r * normal
        return side * (v - ORIGIN_PX[1]) - _outline_half_width(u)

    return point + sign * brentq(beyond_outline, -50.0, 200.0) * normal


def _synthetic_annotation(rng):
    """A user's annotation of the true animal: four midline clicks and, along the stations
    of that noisy midline, the two outline crossings, every click off by N(0, σ²) per axis."""
    fractions = np.array([0.0, 1 / 3, 2 / 3, 1.0])
    clicks = ORIGIN_PX + np.outer(fractions, [BL_M / M_PER_PX, 0.0])
    clicks = clicks + rng.normal(0.0, CLICK_SD_PX, clicks.shape)
    stations = place_stations(clicks)
    edges = np.array([[_clicked_edge(p, n, 1.0), _clicked_edge(p, n, -1.0)]
                      for p, n in zip(stations.points_px, stations.normals)])
    return Annotation(0, clicks, edges + rng.normal(0.0, CLICK_SD_PX, edges.shape))


def test_95_percent_intervals_cover_the_truth_95_percent_of_the_time():
    """400 synthetic annotations with known click, altitude, focal and HW errors: the share of
    95 % intervals holding the true length, volume and mass lies within 3 binomial SDs
    (√(0.95·0.05/400) = 1.1 %) of 95 %, i.e. in [0.917, 0.983]. Measured: length 0.945,
    volume 0.970, mass 0.9625 (and 0.955, 0.947, 0.945 over 3000 repeats)."""
    rng = np.random.default_rng(1)
    ratios, ratio_sd = HW.completed()
    errors = ErrorModel(LASER_SD, FOCAL_SD, CLICK_SD_PX, 1.0)
    hits = np.zeros(3)
    for _ in range(COVERAGE_REPEATS):
        true_hw = ratios + rng.normal() * ratio_sd
        true_volume = elliptical_volume(BL_M, W_BL * BL_M, true_hw, TAIL_EXTRAPOLATED)
        truth = (BL_M, true_volume, body_condition(BL_M, true_volume).mass_kg)
        pixels = pixel_measurements(_synthetic_annotation(rng))
        altitude = ALTITUDE_M * (1 + rng.normal(0.0, LASER_SD))
        focal = FOCAL_PX * (1 + rng.normal(0.0, FOCAL_SD))
        mc = monte_carlo(pixels, focal, altitude, HW, TAIL_EXTRAPOLATED, errors,
                         COVERAGE_DRAWS, rng)
        for idx, (summary, true_value) in enumerate(zip(
                (mc.length_m, mc.volume_m3, mc.mass_kg), truth)):
            hits[idx] += float(summary.low) <= float(true_value) <= float(summary.high)
    coverage = hits / COVERAGE_REPEATS
    assert ((coverage >= 0.917) & (coverage <= 0.983)).all(), coverage
