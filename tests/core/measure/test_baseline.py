"""The end-to-end baseline estimate: what it warns about and what its JSON holds."""

import json

import numpy as np
import pytest

from dolphinfit.core.measure.annotation import PixelMeasurements
from dolphinfit.core.measure.baseline import BaselineSettings, estimate_baseline
from dolphinfit.core.measure.elliptical import TAIL_MEASURED
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.uncertainty import ErrorModel

# Provisional template widths / BL (reference/morphometrics.md §4), 2.5 m at 5 mm/px
W_BL = np.array([.045, .085, .13, .15, .165, .175, .18, .18, .175, .16, .14, .125, .11, .09,
                 .075, .06, .045, .030, .015])
FOCAL_PX, ALTITUDE_M = 4000.0, 20.0


def _estimate(widths_bl, tail, num_draws=0):
    pixels = PixelMeasurements(500.0, widths_bl * 500.0, False)
    settings = BaselineSettings(load_hw_preset(), tail)
    return estimate_baseline(pixels, FOCAL_PX, ALTITUDE_M, settings,
                             ErrorModel.default("laser", False), num_draws,
                             np.random.default_rng(0))


def test_warnings_name_provisional_ratios_carried_tail_filled_stations_and_bci():
    """Measured tail with the provisional prior, two skipped stations, BCI ≈ +0.44: four
    warnings, each saying what to look out for."""
    widths = W_BL * 1.1
    widths[[2, 10]] = np.nan
    estimate = _estimate(widths, TAIL_MEASURED)
    warnings = estimate.warnings()
    assert len(warnings) == 4
    assert "'tursiops-provisional' are provisional" in warnings[0]
    assert "85 % ratio is carried" in warnings[1]
    assert warnings[2].endswith("interpolation: 15 %, 55 %")
    assert float(estimate.point.condition.bci) == pytest.approx(0.4433, abs=1e-4)
    assert "lies outside -0.3…+0.3" in warnings[3]


def test_json_without_monte_carlo_is_plain_and_complete():
    """No draws: no interval or budget; the JSON holds the per-station table and settings."""
    estimate = _estimate(W_BL, TAIL_MEASURED)
    assert estimate.interval is None and estimate.budget == {}
    data = json.loads(json.dumps(estimate.to_json()))
    assert data["uncertainty"] is None and data["length_m"] == pytest.approx(2.5)
    assert data["m_per_px"] == pytest.approx(0.005)
    station = data["stations"][16]
    assert (station["station_pct"], station["hw_ratio"], station["is_filled"]) == \
        (85.0, 2.4, False)
    assert station["height_m"] == pytest.approx(0.045 * 2.5 * 2.4)
    assert data["settings"]["mass_model"]["density_intercept_kg_m3"] == 1000.71


def test_json_with_monte_carlo_has_intervals_and_the_budget():
    """With draws: mean, SD and interval per quantity, per-station widths, SD by source."""
    data = json.loads(json.dumps(_estimate(W_BL, TAIL_MEASURED, 200).to_json()))
    uncertainty = data["uncertainty"]
    assert uncertainty["num_draws"] == 200 and uncertainty["errors"]["altitude_sd_fraction"] == 0.01
    assert set(uncertainty["mass_kg"]) == {"mean", "sd", "low", "high"}
    assert len(uncertainty["widths_m"]["low"]) == 19
    assert set(uncertainty["budget_sd"]) == {"altitude", "camera", "digitisation", "hw_ratios"}
