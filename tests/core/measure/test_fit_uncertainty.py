"""The fit's Monte Carlo: collapse without error, exact scalings per source, and the
comparison's fit interval on the elliptical estimate's error model."""

from types import SimpleNamespace

import numpy as np
import pytest
import torch

from dolphinfit.core.measure.annotation import PixelMeasurements
from dolphinfit.core.measure.baseline import BaselineSettings, estimate_baseline
from dolphinfit.core.measure.condition import body_condition
from dolphinfit.core.measure.fit_uncertainty import fit_interval, outline_sd_px
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.mesh import body_length, mesh_volume
from dolphinfit.core.measure.uncertainty import ErrorModel
from dolphinfit.core.model.template import load_template
from dolphinfit.core.project.comparison import compare

HW = load_hw_preset()
RATIOS, RATIO_SD = HW.completed()
BL_M, VOLUME_M3, M_PER_PX = 2.5, 0.2, 0.0146   # 19.5 m over a 1080p frame
WIDTHS = np.full(19, 0.4)
HEIGHTS = WIDTHS * RATIOS
NO_ERROR = ErrorModel(0.0, 0.0, 0.0, 0.0)
Z975 = 1.959964


def _interval(errors=NO_ERROR, outline_sd_px=0.0, widths=WIDTHS, heights=HEIGHTS, draws=20000):
    return fit_interval(BL_M, VOLUME_M3, widths, heights, M_PER_PX, errors, HW,
                        np.random.default_rng(0), outline_sd_px=outline_sd_px,
                        num_draws=draws)


def test_the_default_outline_sd_grows_with_the_frame():
    assert outline_sd_px(1920) == pytest.approx(0.365, abs=0.005)
    assert outline_sd_px(3840) == pytest.approx(2 * outline_sd_px(1920))


def test_zero_error_collapses_onto_the_fit():
    interval = _interval(draws=50)
    condition = body_condition(np.float64(BL_M), np.float64(VOLUME_M3))
    for name, value in (("length_m", BL_M), ("volume_m3", VOLUME_M3),
                        ("bci", condition.bci), ("density_kg_m3", condition.density_kg_m3),
                        ("mass_kg", condition.mass_kg)):
        summary = getattr(interval, name)
        assert float(summary.sd) == pytest.approx(0.0, abs=1e-12)
        assert float(summary.low) == pytest.approx(float(value), rel=1e-12)
        assert float(summary.high) == pytest.approx(float(value), rel=1e-12)


def test_altitude_error_scales_length_and_cubes_volume():
    interval = _interval(ErrorModel(0.02, 0.0, 0.0, 0.0))
    for bound, z in (("low", -Z975), ("high", Z975)):
        scale = 1 + z * 0.02
        assert float(getattr(interval.length_m, bound)) == pytest.approx(BL_M * scale, rel=0.003)
        assert float(getattr(interval.volume_m3, bound)) == pytest.approx(
            VOLUME_M3 * scale ** 3, rel=0.01)


def test_an_outline_offset_moves_length_by_twice_it_and_widths_with_heights():
    """δ px outside: the length grows by 2δ, each width by 2δ and its height with it, so on
    equal widths w the volume is V·((w + 2δ)/w)²."""
    sd_px = 0.5
    interval = _interval(outline_sd_px=sd_px)
    grown_m = 2 * Z975 * sd_px * M_PER_PX
    assert float(interval.length_m.sd) == pytest.approx(2 * sd_px * M_PER_PX, rel=0.02)
    assert float(interval.length_m.high) == pytest.approx(BL_M + grown_m, rel=1e-3)
    assert float(interval.volume_m3.high) == pytest.approx(
        VOLUME_M3 * ((0.4 + grown_m) / 0.4) ** 2, rel=0.003)
    assert float(interval.volume_m3.low) == pytest.approx(
        VOLUME_M3 * ((0.4 - grown_m) / 0.4) ** 2, rel=0.003)


def test_narrow_bodies_are_more_sensitive_to_the_outline():
    wide, narrow = _interval(outline_sd_px=0.3), _interval(outline_sd_px=0.3, widths=WIDTHS / 2,
                                                          heights=HEIGHTS / 2)
    ratio = float(narrow.volume_m3.sd) / float(wide.volume_m3.sd)
    assert ratio == pytest.approx(2.0, rel=0.02)


def test_hidden_heights_move_the_volume_by_the_tables_relative_sd():
    interval = _interval(ErrorModel(0.0, 0.0, 0.0, 1.0))
    weights = WIDTHS * HEIGHTS
    relative = float((weights * RATIO_SD / RATIOS).sum() / weights.sum())
    assert relative > 0
    assert float(interval.volume_m3.high) == pytest.approx(
        VOLUME_M3 * (1 + Z975 * relative), rel=0.005)
    assert float(interval.length_m.sd) == 0.0


@pytest.mark.parametrize("change", [{"num_draws": 1}, {"volume_m3": 0.0},
                                    {"widths_m": np.zeros(19)}, {"outline_sd_px": -0.1}])
def test_bad_inputs_are_refused(change):
    args = dict(length_m=BL_M, volume_m3=VOLUME_M3, widths_m=WIDTHS, heights_m=HEIGHTS,
                m_per_px=M_PER_PX, errors=NO_ERROR, hw=HW, rng=np.random.default_rng(0),
                outline_sd_px=0.3)
    with pytest.raises(ValueError):
        fit_interval(**(args | change))


def test_the_comparison_gives_the_fit_an_interval_beside_the_elliptical_one():
    """The template as the fitted animal, beside an elliptical estimate of 2.5 m seen from 20 m
    with the laser altimeter's error model: both methods get an interval around their value; the
    fit's volume interval is wider than its altitude error alone makes it (outline, heights)."""
    template = load_template()
    verts, faces = torch.as_tensor(template.verts), torch.as_tensor(template.faces)
    fit = SimpleNamespace(
        rest_verts=template.verts, volume_m3=float(mesh_volume(verts, faces)),
        length_m=float(body_length(verts, template.rostrum_idx, template.notch_idx)),
        edge_blur_px=float("nan"))   # not measured: the frame-width rule
    condition = body_condition(np.float64(fit.length_m), np.float64(fit.volume_m3))
    fit.bci, fit.density_kg_m3 = float(condition.bci), float(condition.density_kg_m3)
    fit.mass_kg = float(condition.mass_kg)
    widths_px = 0.17 * BL_M / M_PER_PX * np.sin(np.linspace(0.2, 2.9, 19))
    pixels = PixelMeasurements(BL_M / M_PER_PX, widths_px, False)
    errors = ErrorModel.default("laser", False)
    estimate = estimate_baseline(pixels, 1.0 / M_PER_PX, 1.0, BaselineSettings(HW), errors,
                                 2000, np.random.default_rng(0))
    rows = {row.key: row for row in compare(estimate, fit, 1920)}
    for row in rows.values():
        for method in (row.elliptical, row.fitted):
            assert method.low < method.value < method.high
    volume = rows["volume_m3"].fitted
    altitude_only = 2 * Z975 * 3 * errors.altitude_sd_fraction * volume.value
    assert volume.high - volume.low > 1.5 * altitude_only
    no_draws = estimate_baseline(pixels, 1.0 / M_PER_PX, 1.0, BaselineSettings(HW), errors,
                                 0, np.random.default_rng(0))
    assert all(row.fitted.low is None for row in compare(no_draws, fit, 1920))
    wider = {row.key: row for row in compare(estimate, fit, 3840)}["volume_m3"].fitted
    assert wider.high - wider.low > volume.high - volume.low  # twice the outline SD in px
