"""Screen-space barycentric interpolation at covered pixels, with gradients to the vertices.

The barycentrics are recomputed from the grad-enabled projected vertices of each pixel's
front-most face (DIB-R: screen-space, not perspective-correct), so attribute gradients reach
vertex positions through d(weights)/d(2-D vertex); depth gets none.
"""

import torch

from dolphinfit.core.render.rasterize import Fragments, edge_weights, gather_corners


def barycentrics(xy_px: torch.Tensor, faces: torch.Tensor, frags: Fragments) -> torch.Tensor:
    """(C, 3) weights of the covered pixels in their faces; xy_px: (T, V, 2)."""
    tri = gather_corners(xy_px, faces, frags.frame, frags.face)  # (C, 3, 2)
    return edge_weights(tri, frags.pixel_centres(xy_px.dtype))


def interpolate_vertex_values(values: torch.Tensor, faces: torch.Tensor, frags: Fragments,
                              weights: torch.Tensor) -> torch.Tensor:
    """(C, D) per-vertex ``values`` (T, V, D) interpolated at the covered pixels."""
    flat_idx = frags.frame[:, None] * values.shape[1] + faces[frags.face]
    corner = values.reshape(-1, values.shape[-1]).index_select(0, flat_idx.reshape(-1))
    return weighted_sum(weights, corner.reshape(*flat_idx.shape, values.shape[-1]))


def interpolate_corner_values(corner_values: torch.Tensor, frags: Fragments,
                              weights: torch.Tensor) -> torch.Tensor:
    """(C, D) per-face-corner ``corner_values`` (F, 3, D) interpolated at covered pixels."""
    return weighted_sum(weights, corner_values.index_select(0, frags.face))


def weighted_sum(weights: torch.Tensor, values: torch.Tensor) -> torch.Tensor:
    """(C, D) Σ_k weights[:, k] · values[:, k] for weights (C, K) and values (C, K, D),
    written out over k: torch reduces a short middle axis several times slower."""
    total = weights[:, :1] * values[:, 0]
    for k in range(1, weights.shape[1]):
        total = total + weights[:, k:k + 1] * values[:, k]
    return total
