"""Measurements on model meshes, differentiable, batched over leading dimensions.

Shapes: V vertices, F faces, S stations, R vertices per station ring; ``...`` any batch
(e.g. T frames). Units follow the vertices (metres).
"""

from dataclasses import dataclass

import torch


def mesh_volume(verts: torch.Tensor, faces: torch.Tensor) -> torch.Tensor:
    """(...) enclosed volume by the divergence theorem: Σ_f v0 · (v1 × v2) / 6.

    verts: (..., V, 3); faces: (F, 3) int64. Meaningful only for a closed mesh with
    consistent outward winding (the template's, under any β and θ); then it is exact.
    """
    v0, v1, v2 = (verts[..., faces[:, k], :] for k in range(3))
    return (v0 * torch.linalg.cross(v1, v2, dim=-1)).sum(dim=(-1, -2)) / 6.0


def body_length(verts: torch.Tensor, rostrum_idx: int, notch_idx: int) -> torch.Tensor:
    """(...) straight distance from the rostrum tip to the fluke notch."""
    return torch.linalg.vector_norm(verts[..., rostrum_idx, :] - verts[..., notch_idx, :], dim=-1)


@dataclass(frozen=True)
class StationProfile:
    """Body width and height at each station (fins excluded)."""

    width: torch.Tensor   # (..., S) lateral extent
    height: torch.Tensor  # (..., S) dorso-ventral extent


def station_profile(verts: torch.Tensor, rings: torch.Tensor) -> StationProfile:
    """Width and height of each station ring, in the ring's own frame.

    verts: (..., V, 3); rings: (S, R) int64 with the two vertices flanking the dorsal
    midline first and last. The ring's normal (its area vector) is the local body axis, the
    dorsal direction points from the ring centroid to the dorsal pair, and the lateral
    direction completes the frame; extents are taken along those two directions, so the
    measure follows a posed, bent or rolled body.
    """
    points = verts[..., rings, :]                                   # (..., S, R, 3)
    centre = points.mean(dim=-2, keepdim=True)
    rel = points - centre
    area = torch.linalg.cross(rel, torch.roll(rel, -1, dims=-2), dim=-1).sum(dim=-2)
    axis = area / torch.linalg.vector_norm(area, dim=-1, keepdim=True)
    dorsal = 0.5 * (rel[..., 0, :] + rel[..., -1, :])
    dorsal = dorsal - (dorsal * axis).sum(-1, keepdim=True) * axis
    dorsal = dorsal / torch.linalg.vector_norm(dorsal, dim=-1, keepdim=True)
    lateral = torch.linalg.cross(axis, dorsal, dim=-1)
    along_lateral = (rel * lateral[..., None, :]).sum(-1)
    along_dorsal = (rel * dorsal[..., None, :]).sum(-1)
    return StationProfile(
        width=along_lateral.amax(-1) - along_lateral.amin(-1),
        height=along_dorsal.amax(-1) - along_dorsal.amin(-1),
    )
