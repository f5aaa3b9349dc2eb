"""Small scenes with known content for the renderer tests."""

import math

import numpy as np
import torch
import trimesh

from dolphinfit.core.camera import NadirCamera
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.render.render import Appearance
from dolphinfit.core.render.shade import SGLight


def ellipsoid(radii, centre, subdivisions=1):
    """(V, 3) vertices, (F, 3) faces and (F, 3, 2) corner UVs of an outward-wound ellipsoid."""
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions)
    verts = sphere.vertices * np.asarray(radii) + np.asarray(centre)
    faces = sphere.faces
    unit = sphere.vertices[faces]                                    # (F, 3, 3)
    u = (np.arctan2(unit[..., 1], unit[..., 0]) / (2 * math.pi)) % 1.0
    v = np.arccos(np.clip(unit[..., 2], -1, 1)) / math.pi
    return verts, faces, np.stack([u, v], -1)


def two_ellipsoids(dtype=torch.float64):
    """Two overlapping ellipsoids at different depths: (verts (V, 3), faces, face UVs)."""
    v1, f1, uv1 = ellipsoid((0.6, 0.3, 0.2), (0.0, 0.0, -0.3))
    v2, f2, uv2 = ellipsoid((0.35, 0.2, 0.12), (0.35, 0.15, 0.1))
    verts = np.concatenate([v1, v2])
    faces = np.concatenate([f1, f2 + len(v1)])
    return (torch.tensor(verts, dtype=dtype), torch.tensor(faces, dtype=torch.int64),
            torch.tensor(np.concatenate([uv1, uv2]), dtype=dtype))


def appearance(face_uvs, dtype=torch.float64, seed=0):
    """A random grey texture, the default light and a reddish water filter."""
    gen = torch.Generator().manual_seed(seed)
    texture = torch.rand(12, 16, generator=gen, dtype=dtype)
    return Appearance(albedo=texture, face_uvs=face_uvs, light=SGLight.overhead_sun(dtype),
                      f_water=torch.tensor([0.6, 0.25, 0.1], dtype=dtype))


def camera(width_px, height_px, altitudes, refraction=True):
    """The paper's camera at the given image size and per-frame altitudes."""
    intrinsics = CameraIntrinsics.from_sensor(12.29, 17.27, width_px, height_px)
    return NadirCamera(intrinsics, torch.tensor(altitudes, dtype=torch.float64),
                       refraction=refraction)


def moved(verts, translations, yaw_rad=0.0):
    """(T, V, 3) copies of ``verts`` rotated about z by ``yaw_rad`` and translated."""
    c, s = math.cos(yaw_rad), math.sin(yaw_rad)
    rot = torch.tensor([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]], dtype=verts.dtype)
    base = verts @ rot.T
    return torch.stack([base + torch.tensor(t, dtype=verts.dtype) for t in translations])
