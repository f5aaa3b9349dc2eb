"""Mesh measurements against analytic shapes."""

import math

import numpy as np
import pytest
import torch
import trimesh

from dolphinfit.core.measure.mesh import body_length, mesh_volume, station_profile


def test_volume_of_a_box_and_a_sphere():
    """A 1×2×3 box has volume 6; an icosphere matches its own exact polyhedral volume."""
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    assert float(mesh_volume(torch.tensor(box.vertices), torch.tensor(box.faces))) == \
        pytest.approx(6.0, rel=1e-12)
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=0.5)
    volume = float(mesh_volume(torch.tensor(sphere.vertices), torch.tensor(sphere.faces)))
    assert volume == pytest.approx(sphere.volume, rel=1e-12)
    assert volume == pytest.approx(4 / 3 * math.pi * 0.125, rel=5e-3)


def test_volume_is_translation_invariant_and_batched():
    """Shifting a closed mesh leaves the volume unchanged; leading dims are batches."""
    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    verts = torch.tensor(box.vertices)
    batch = torch.stack([verts, verts + torch.tensor([5.0, -3.0, 2.0])])
    torch.testing.assert_close(mesh_volume(batch, torch.tensor(box.faces)),
                               torch.ones(2, dtype=torch.float64))


def test_body_length_is_the_landmark_distance():
    """Length is the straight rostrum–notch distance."""
    verts = torch.tensor([[0.0, 0.0, 0.0], [3.0, 4.0, 0.0], [1.0, 1.0, 1.0]])
    assert float(body_length(verts, 1, 0)) == pytest.approx(5.0)


def _elliptic_rings(half_width, half_height, num=24, positions=(0.0, 0.5)):
    """Rings of an elliptic tube along x, dorsal pair at both ends of each ring."""
    phi = (np.arange(num) + 0.5) / num * 2 * np.pi
    rings = [np.stack([np.full(num, x), half_width * np.sin(phi), half_height * np.cos(phi)], 1)
             for x in positions]
    return torch.tensor(np.concatenate(rings)), torch.arange(num * len(positions)).reshape(-1, num)


def test_station_profile_of_an_elliptic_tube_in_any_orientation():
    """Width and height of elliptic rings are their axes, whatever the body's rotation."""
    verts, rings = _elliptic_rings(0.3, 0.2, num=400)
    rotation = torch.tensor(trimesh.transformations.random_rotation_matrix(
        rand=np.array([0.1, 0.7, 0.3]))[:3, :3])
    moved = verts @ rotation.T + torch.tensor([4.0, -1.0, 2.0], dtype=torch.float64)
    for mesh_verts in (verts, moved):
        profile = station_profile(mesh_verts, rings)
        np.testing.assert_allclose(profile.width.numpy(), 0.6, rtol=1e-4)
        np.testing.assert_allclose(profile.height.numpy(), 0.4, rtol=1e-4)
