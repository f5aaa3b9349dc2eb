"""The elliptical solid: watertight, outward, and its volume is the 20-frustum volume."""

import math

import numpy as np
import pytest
import trimesh

from dolphinfit.core.measure.elliptical import (
    TAIL_EXTRAPOLATED, apply_tail, elliptical_volume, segment_volumes,
)
from dolphinfit.core.measure.elliptical_solid import elliptical_solid
from dolphinfit.core.measure.stations import STATION_FRACTIONS

BL_M = 2.5
# Provisional template widths / BL at 5 … 95 % and HW ratios (as in test_elliptical.py)
TEMPLATE_W_BL = np.array([.045, .085, .13, .15, .165, .175, .18, .18, .175, .16, .14, .125,
                          .11, .09, .075, .06, .045, .030, .015])
HW = np.repeat([1.0, 1.125, 1.4, 1.625, 2.4, 2.4], [3, 5, 3, 4, 2, 2])
# The mesh volume equals ratio × frustum volume to rounding (the quad twists cancel exactly)
REL_TOL = 1e-12


def _polygon_ratio(n: int) -> float:
    """Area of an n-gon inscribed in an ellipse over the ellipse's area."""
    return n / (2 * math.pi) * math.sin(2 * math.pi / n)


def _mesh(widths: np.ndarray, heights: np.ndarray, n: int) -> trimesh.Trimesh:
    verts, faces = elliptical_solid(BL_M, widths, heights, ring_points=n)
    return trimesh.Trimesh(verts, faces, process=False)


@pytest.mark.parametrize("n", [3, 8, 32, 128])
def test_cylinder_like_solid_is_watertight_with_the_frustum_volume(n):
    widths = np.full(19, 0.4)
    mesh = _mesh(widths, widths, n)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume > 0  # outward winding
    expected = segment_volumes(BL_M, widths, widths).sum()
    assert mesh.volume == pytest.approx(_polygon_ratio(n) * expected, rel=REL_TOL)


@pytest.mark.parametrize("n", [4, 16, 64])
def test_real_profile_matches_the_elliptical_volume(n):
    widths = apply_tail(TEMPLATE_W_BL * BL_M, TAIL_EXTRAPOLATED)
    heights = apply_tail(TEMPLATE_W_BL * BL_M * HW, TAIL_EXTRAPOLATED)
    mesh = _mesh(widths, heights, n)
    assert mesh.is_watertight and mesh.is_winding_consistent
    expected = elliptical_volume(BL_M, TEMPLATE_W_BL * BL_M, HW, TAIL_EXTRAPOLATED)
    assert mesh.volume == pytest.approx(_polygon_ratio(n) * expected, rel=REL_TOL)


def test_volume_approaches_the_formula_as_rings_refine():
    widths, heights = TEMPLATE_W_BL * BL_M, TEMPLATE_W_BL * BL_M * HW
    expected = segment_volumes(BL_M, widths, heights).sum()
    errors = [abs(_mesh(widths, heights, n).volume / expected - 1) for n in (16, 64, 256)]
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 1.1e-4  # (2π/n)²/6 ≈ 1.0e-4 at n = 256


def test_layout_is_centred_with_the_rostrum_towards_plus_x():
    widths, heights = TEMPLATE_W_BL * BL_M, TEMPLATE_W_BL * BL_M * HW
    verts, _ = elliptical_solid(BL_M, widths, heights, ring_points=4)
    assert verts[0] == pytest.approx([BL_M / 2, 0, 0])
    assert verts[-1] == pytest.approx([-BL_M / 2, 0, 0])
    widest = np.argmax(widths)
    ring = verts[1 + 4 * widest: 1 + 4 * (widest + 1)]
    assert ring[:, 0] == pytest.approx(BL_M * (0.5 - STATION_FRACTIONS[widest]))
    assert np.ptp(verts[:, 1]) == pytest.approx(widths.max())
    assert np.ptp(verts[:, 2]) == pytest.approx(heights.max())


@pytest.mark.parametrize("widths, ring_points", [(np.full(18, 0.4), 8),
                                                 (np.full(19, np.nan), 8),
                                                 (np.full(19, -0.1), 8),
                                                 (np.full(19, 0.4), 2)])
def test_bad_inputs_are_refused(widths, ring_points):
    with pytest.raises(ValueError):
        elliptical_solid(BL_M, widths, np.abs(widths), ring_points)
