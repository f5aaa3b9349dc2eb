"""Template sections with other heights or shapes: for the fit's hidden heights and for
synthetic animals unlike the template."""

import json
import math
from dataclasses import replace

import numpy as np
import pytest
import torch
import trimesh

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.mesh import body_length, mesh_volume, station_profile
from dolphinfit.core.model.template import load_template
from dolphinfit.core.model.sections import reshape_sections, section_area_factor
from dolphinfit.core.synth.clip import make_clip
from dolphinfit.core.synth.config import Effects, SynthConfig
from dolphinfit.core.synth.shape import draw_hw


def _figures(template):
    verts = torch.as_tensor(template.verts)
    profile = station_profile(verts, torch.as_tensor(template.station_rings))
    return (float(mesh_volume(verts, torch.as_tensor(template.faces))),
            float(body_length(verts, template.rostrum_idx, template.notch_idx)),
            profile.width.numpy(), profile.height.numpy())


def test_area_factor_is_one_for_ellipses_and_known_for_others():
    """n = 2 is the ellipse (π/4·w·h); n = 1 a rhombus (w·h/2); large n nears the rectangle."""
    assert section_area_factor(2.0) == pytest.approx(1.0, abs=1e-12)
    assert section_area_factor(1.0) == pytest.approx(2.0 / math.pi, abs=1e-12)
    assert section_area_factor(200.0) == pytest.approx(4.0 / math.pi, rel=0.01)


def test_template_heights_and_ellipses_change_nothing():
    template = load_template()
    np.testing.assert_allclose(reshape_sections(template, None, 2.0).verts, template.verts,
                               rtol=0, atol=1e-12)


def test_heights_follow_the_table_and_widths_length_stay():
    """With the table's mean ratios the 5–85 % stations carry exactly those ratios; widths,
    length and the mesh's closedness are untouched, and the volume grows (the table's ratios
    are larger than the template's over the tail stock)."""
    template = load_template()
    table = load_hw_preset("tursiops-provisional")
    reshaped = reshape_sections(template, table.completed()[0][:17])
    volume0, length0, width0, _ = _figures(template)
    volume, length, width, height = _figures(reshaped)
    np.testing.assert_allclose(height[:17] / width[:17], table.ratios[:17], rtol=2e-3)
    np.testing.assert_allclose(width, width0, rtol=1e-9)
    assert length == pytest.approx(length0, rel=1e-12)
    assert 1.08 < volume / volume0 < 1.13
    assert trimesh.Trimesh(reshaped.verts, reshaped.faces, process=False).is_volume


@pytest.mark.parametrize("exponent", [1.8, 2.3])
def test_fuller_sections_add_their_area_factor_of_volume(exponent):
    """The body's volume scales by the superellipse's area factor (the fins, which only move,
    and the faceting keep it within half a per cent); widths and heights stay (to the
    faceting: the ring's lateral vertices sit 2° off the lateral midline)."""
    template = load_template()
    volume0, _, width0, height0 = _figures(template)
    volume, _, width, height = _figures(reshape_sections(template, None, exponent))
    assert volume / volume0 == pytest.approx(section_area_factor(exponent), rel=5e-3)
    np.testing.assert_allclose(width, width0, rtol=5e-3)
    np.testing.assert_allclose(height, height0, rtol=5e-3)


def test_drawn_heights_scatter_around_the_table_by_its_sd():
    table = load_hw_preset("tursiops-provisional")
    rng = np.random.default_rng(7)
    draws = np.stack([draw_hw(table, rng) for _ in range(2000)])
    ratios, sd = table.completed()
    assert np.all(np.abs(draws.mean(0) - ratios[:17]) <= 4 * sd[:17] / math.sqrt(2000))
    np.testing.assert_allclose(draws.std(0), sd[:17], rtol=0.15)
    # neighbouring stations move together (a smooth animal, not station noise)
    assert np.corrcoef(draws[:, 5], draws[:, 6])[0, 1] > 0.8
    again = draw_hw(table, np.random.default_rng(7))
    assert np.array_equal(again, draws[0])


def test_config_checks_the_shape_options():
    with pytest.raises(InputError, match="hw_table"):
        SynthConfig(hw_table="no-such-table")
    with pytest.raises(InputError, match="section_exponent"):
        SynthConfig(section_exponent=5.0)
    assert SynthConfig(hw_table="circular").hw_table == "circular"


def test_clip_truth_carries_the_drawn_shape(tmp_path):
    """A clip made with an HW table and fuller sections records a larger volume than the
    same clip with the template's shape, by about the table's and the sections' factors."""
    base = SynthConfig(seed=5, width_px=160, height_px=120, fps=5.0, duration_s=0.4,
                       altitude_m=5.0, length_m=2.3, heading_deg=0.0,
                       effects=Effects(profile_warp=False, scattering=False, refraction=False,
                                       ripples=False, glints=False, compression=False))
    plain = json.loads(make_clip(base, tmp_path / "a").truth_json.read_text())
    shaped_config = replace(base, hw_table="tursiops-provisional", section_exponent=2.2)
    shaped = json.loads(make_clip(shaped_config, tmp_path / "b").truth_json.read_text())
    assert shaped["length_m"] == pytest.approx(plain["length_m"], rel=1e-9)
    ratio = shaped["volume_m3"] / plain["volume_m3"]
    assert 1.05 * section_area_factor(2.2) < ratio < 1.16 * section_area_factor(2.2)
    assert shaped["config"]["hw_table"] == "tursiops-provisional"
