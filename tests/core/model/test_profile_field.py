"""The profile field: smooth width and height factors along the body, fins carried along."""

import numpy as np
import pytest
import torch
import trimesh

from dolphinfit.core.measure.mesh import body_length, mesh_volume, station_profile
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.profile_field import NUM_KNOTS, spline_basis


@pytest.fixture(scope="module")
def model64():
    return DolphinModel(dtype=torch.float64)


def _rest(model, profile):
    betas = torch.zeros(model.num_groups, 4, dtype=torch.float64)
    return model.forward_rest(betas, profile)[0]


def _profile(model, verts):
    return station_profile(verts, model.station_rings)


def test_basis_is_a_partition_of_unity():
    t = np.linspace(0.0, 1.0, 101)
    basis = spline_basis(t)
    assert basis.shape == (101, NUM_KNOTS)
    np.testing.assert_allclose(basis.sum(1), 1.0, atol=1e-12)
    assert (basis >= 0).all()


def test_zero_field_is_the_template(model64):
    zero = torch.zeros(2, NUM_KNOTS, dtype=torch.float64)
    np.testing.assert_allclose(_rest(model64, zero).numpy(), _rest(model64, None).numpy(),
                               rtol=0, atol=1e-15)


def test_constant_rows_scale_every_width_and_height(model64):
    """A constant row 0 of log 1.1 widens every station by 10 % and, with row 1 at zero,
    deepens it by 10 % too (the template's ratios stay); row 1 at log 0.9 then flattens the
    heights alone. Length never changes; the mesh stays a closed, unfolded volume."""
    base = _profile(model64, _rest(model64, None))
    wide = torch.zeros(2, NUM_KNOTS, dtype=torch.float64)
    wide[0] = np.log(1.1)
    rest = _rest(model64, wide)
    shaped = _profile(model64, rest)
    np.testing.assert_allclose((shaped.width / base.width).numpy(), 1.1, rtol=1e-9)
    np.testing.assert_allclose((shaped.height / base.height).numpy(), 1.1, rtol=1e-9)
    flat = wide.clone()
    flat[1] = np.log(0.9)
    shaped = _profile(model64, _rest(model64, flat))
    np.testing.assert_allclose((shaped.width / base.width).numpy(), 1.1, rtol=1e-9)
    np.testing.assert_allclose((shaped.height / base.height).numpy(), 0.99, rtol=1e-9)
    template_rest = _rest(model64, None)
    assert float(body_length(rest, model64.rostrum_idx, model64.notch_idx)) == pytest.approx(
        float(body_length(template_rest, model64.rostrum_idx, model64.notch_idx)), rel=1e-12)
    mesh = trimesh.Trimesh(rest.numpy(), model64.faces.numpy(), process=False)
    assert mesh.is_volume
    # the body's volume (fins merely carried) grows by the product of both factors
    ratio = float(mesh_volume(rest, model64.faces) / mesh_volume(template_rest, model64.faces))
    assert 1.19 < ratio < 1.21


def test_one_knot_changes_only_its_stretch_of_body(model64):
    """The 6th B-spline (support 2/7–6/7 of the body) widens the stations there and leaves
    those ahead of it (5–25 %) and behind it (90, 95 %) as they were."""
    base = _profile(model64, _rest(model64, None)).width
    bump = torch.zeros(2, NUM_KNOTS, dtype=torch.float64)
    bump[0, 5] = 0.2
    ratio = (_profile(model64, _rest(model64, bump)).width / base).numpy()
    np.testing.assert_allclose(ratio[[0, 1, 2, 3, 4, 17, 18]], 1.0, atol=1e-12)
    assert ratio[10] > 1.05


def test_fins_ride_on_the_body_unstretched(model64):
    """Deepening the body lifts the dorsal fin rigidly: every fin vertex moves by the same
    vector, the mean displacement of its base."""
    template = model64.profile_field
    deep = torch.zeros(2, NUM_KNOTS, dtype=torch.float64)
    deep[1] = np.log(1.2)
    moved = _rest(model64, deep) - _rest(model64, None)
    fin, base = template.fins[0]
    np.testing.assert_allclose(moved[fin].numpy(), moved[fin][:1].expand(len(fin), 3).numpy(),
                               atol=1e-12)
    np.testing.assert_allclose(moved[fin][0].numpy(), moved[base].mean(0).numpy(), atol=1e-12)
    assert float(moved[fin][0, 2]) != 0.0


def test_field_gradients_match_finite_differences(model64):
    coefficients = (0.05 * torch.randn(2, NUM_KNOTS, dtype=torch.float64,
                                       generator=torch.Generator().manual_seed(0)))
    coefficients.requires_grad_()

    def volume(c):
        return mesh_volume(_rest(model64, c), model64.faces)

    assert torch.autograd.gradcheck(volume, (coefficients,), eps=1e-6, atol=1e-7)


def test_bad_coefficient_shapes_are_rejected(model64):
    with pytest.raises(ValueError, match="profile coefficients"):
        _rest(model64, torch.zeros(3, NUM_KNOTS, dtype=torch.float64))
