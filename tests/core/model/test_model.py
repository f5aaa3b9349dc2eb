"""The parametric model M(β, θ, P): identity, scaling, skinning, symmetry, gradients."""

import math

import numpy as np
import pytest
import torch
import trimesh

from dolphinfit.core.measure.mesh import body_length, mesh_volume, station_profile
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.template import load_template


@pytest.fixture(scope="module")
def model64():
    return DolphinModel(dtype=torch.float64)


def _group(model, name):
    return model.group_names.index(name)


def _rest_fraction(model):
    """Position of each rest vertex along the body, as a fraction of BL from the rostrum."""
    x = model.rest_verts[:, 0]
    return (x[model.rostrum_idx] - x) / (x[model.rostrum_idx] - x[model.notch_idx])


def test_zero_parameters_reproduce_the_template(model64):
    """β = 0, θ = 0, P = 0 gives the template's vertices for every frame, in both dtypes."""
    template = load_template()
    out = model64(*model64.zero_params(3))
    assert out.verts.shape == (3, len(template.verts), 3)
    np.testing.assert_allclose(out.verts.numpy(), np.broadcast_to(template.verts, (3,) +
                               template.verts.shape), rtol=0, atol=1e-12)
    np.testing.assert_allclose(out.joints[0].numpy(), template.rest_joints, atol=1e-12)
    model32 = DolphinModel()
    out32 = model32(*model32.zero_params(1))
    assert out32.verts.dtype == torch.float32
    np.testing.assert_allclose(out32.verts[0].numpy(), template.verts, atol=2e-6)


@pytest.mark.parametrize("scale", [0.8, 1.15])
def test_uniform_scaling_scales_volume_by_cube_and_length_linearly(model64, scale):
    """Scaling every part uniformly by s multiplies volume by s³ and length by s."""
    betas, pose, transl = model64.zero_params(1)
    rest = model64.forward_rest(betas)[0]
    betas[:, 0] = math.log(scale)
    shaped = model64.forward_rest(betas)[0]
    faces = model64.faces
    assert mesh_volume(shaped, faces) / mesh_volume(rest, faces) == pytest.approx(scale**3,
                                                                                   rel=1e-12)
    ratio = (body_length(shaped, model64.rostrum_idx, model64.notch_idx)
             / body_length(rest, model64.rostrum_idx, model64.notch_idx))
    assert ratio == pytest.approx(scale, rel=1e-12)
    widths = station_profile(torch.stack([rest, shaped]), model64.station_rings).width
    np.testing.assert_allclose((widths[1] / widths[0]).numpy(), scale, rtol=1e-12)


def test_volume_agrees_with_trimesh_on_shaped_posed_meshes(model64):
    """The divergence-theorem volume equals trimesh's to 1e-6 relative."""
    gen = torch.Generator().manual_seed(3)
    betas = 0.15 * (2 * torch.rand(model64.num_groups, 4, generator=gen, dtype=torch.float64) - 1)
    pose = 0.3 * torch.randn(2, model64.num_groups, 3, generator=gen, dtype=torch.float64)
    transl = torch.tensor([[1.0, -2.0, -0.5], [0.3, 0.2, 0.0]], dtype=torch.float64)
    out = model64(betas, pose, transl)
    volumes = mesh_volume(out.verts, model64.faces)
    for frame in range(2):
        mesh = trimesh.Trimesh(out.verts[frame].numpy(), model64.faces.numpy(), process=False)
        assert float(volumes[frame]) == pytest.approx(mesh.volume, rel=1e-6)


@pytest.mark.parametrize("part", ["tail0", "tail1", "tail2", "tail3", "tail4", "flukes"])
def test_tail_rotation_moves_nothing_ahead_of_mid_body(model64, part):
    """A 30° stroke at a tail joint moves no vertex ahead of 50 % BL; volume stays within 1 %."""
    betas, pose, transl = model64.zero_params(1)
    rest = model64(betas, pose, transl).verts[0]
    pose[0, _group(model64, part)] = torch.tensor([0.0, math.radians(30.0), 0.0],
                                                  dtype=torch.float64)
    bent = model64(betas, pose, transl).verts[0]
    moved = torch.linalg.vector_norm(bent - rest, dim=-1) > 1e-12
    assert moved.any()
    assert _rest_fraction(model64)[moved].min() >= 0.5
    ratio = mesh_volume(bent, model64.faces) / mesh_volume(rest, model64.faces)
    assert abs(float(ratio) - 1.0) < 0.01


def test_root_pose_and_translation_are_a_rigid_motion(model64):
    """Group 0 rotates the whole body about the root joint, then P translates it."""
    betas, pose, transl = model64.zero_params(1)
    rest = model64(betas, pose, transl).verts[0]
    pose[0, 0] = torch.tensor([0.0, 0.0, math.radians(90.0)], dtype=torch.float64)
    transl[0] = torch.tensor([2.0, 3.0, -1.0], dtype=torch.float64)
    moved = model64(betas, pose, transl).verts[0]
    expected = rest @ torch.tensor([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
                                   dtype=torch.float64) + transl[0]
    torch.testing.assert_close(moved, expected, rtol=0, atol=1e-12)


def test_symmetric_parts_stay_mirror_images(model64):
    """Posing and shaping the shared flipper and fluke parts keeps left and right mirrored."""
    template = load_template()
    betas, pose, transl = model64.zero_params(1)
    for part in ("flippers", "flukes"):
        pose[0, _group(model64, part)] = torch.tensor([0.3, -0.2, 0.4], dtype=torch.float64)
        betas[_group(model64, part)] = torch.tensor([0.1, 0.05, -0.1, 0.2], dtype=torch.float64)
    verts = model64(betas, pose, transl).verts[0].numpy()
    for left, right in (("flipper_l", "flipper_r"), ("fluke_l", "fluke_r")):
        left_pts = verts[template.fin_vertices[left]] * np.array([1.0, -1.0, 1.0])
        right_pts = verts[template.fin_vertices[right]]
        distance = np.linalg.norm(left_pts[:, None] - right_pts[None], axis=-1).min(axis=1)
        assert distance.max() < 1e-9


def test_part_scaling_keeps_the_surface_connected_and_unfolded(model64):
    """Random part scales keep the mesh watertight, with no folded face and no edge torn
    (stretched past 2×) or collapsed (below ½×), blend zones between parts included."""
    gen = torch.Generator().manual_seed(7)
    betas = 0.2 * (2 * torch.rand(model64.num_groups, 4, generator=gen, dtype=torch.float64) - 1)
    rest = model64.rest_verts
    shaped = model64.forward_rest(betas)[0]
    faces = model64.faces
    mesh = trimesh.Trimesh(shaped.numpy(), faces.numpy(), process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.volume > 0

    def normals(verts):
        v0, v1, v2 = (verts[faces[:, k]] for k in range(3))
        return torch.linalg.cross(v1 - v0, v2 - v0, dim=-1)

    assert ((normals(rest) * normals(shaped)).sum(-1) > 0).all()
    edges = torch.tensor(mesh.edges_unique)
    stretch = (torch.linalg.vector_norm(shaped[edges[:, 0]] - shaped[edges[:, 1]], dim=-1)
               / torch.linalg.vector_norm(rest[edges[:, 0]] - rest[edges[:, 1]], dim=-1))
    assert 0.5 < float(stretch.min()) and float(stretch.max()) < 2.0


def test_scaling_one_part_stretches_only_near_it(model64):
    """Enlarging the head leaves the tail in place relative to the root and the root fixed."""
    betas, pose, transl = model64.zero_params(1)
    betas[_group(model64, "head"), 0] = math.log(1.3)
    shaped = model64.forward_rest(betas)[0]
    unaffected = _rest_fraction(model64) > 0.3
    torch.testing.assert_close(shaped[unaffected], model64.rest_verts[unaffected], rtol=0,
                               atol=1e-12)
    assert float(shaped[model64.rostrum_idx, 0] - model64.rest_verts[model64.rostrum_idx, 0]) > 0


def test_gradcheck_float64_reduced_case(model64):
    """Analytic gradients of vertices and volume w.r.t. β, θ, P match finite differences."""
    gen = torch.Generator().manual_seed(11)
    subset = torch.randint(0, model64.rest_verts.shape[0], (12,), generator=gen)
    betas = (0.1 * torch.randn(model64.num_groups, 4, generator=gen, dtype=torch.float64))
    pose = 0.2 * torch.randn(1, model64.num_groups, 3, generator=gen, dtype=torch.float64)
    pose[0, _group(model64, "tail1")] = 0.0  # exercise the zero-angle branch too
    transl = torch.randn(1, 3, generator=gen, dtype=torch.float64)
    inputs = tuple(x.requires_grad_() for x in (betas, pose, transl))

    def verts_subset(b, p, t):
        return model64(b, p, t).verts[:, subset]

    def volume(b, p, t):
        return mesh_volume(model64(b, p, t).verts, model64.faces)

    assert torch.autograd.gradcheck(verts_subset, inputs, eps=1e-6, atol=1e-7)
    assert torch.autograd.gradcheck(volume, inputs, eps=1e-6, atol=1e-7)


def test_bad_parameter_shapes_are_rejected(model64):
    """Wrong β or θ shapes raise an error giving the expected and actual shapes."""
    betas, pose, transl = model64.zero_params(2)
    with pytest.raises(ValueError, match=r"\(11, 4\)"):
        model64(betas[:3], pose, transl)
    with pytest.raises(ValueError, match="transl"):
        model64(betas, pose, transl[:1])
