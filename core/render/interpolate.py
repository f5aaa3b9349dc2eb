"""Screen-space barycentric interpolation at covered pixels, with gradients to the vertices.

The barycentrics are recomputed from the grad-enabled projected vertices of each pixel's
front-most face (DIB-R: screen-space, not perspective-correct), so attribute gradients reach
vertex positions through d(weights)/d(2-D vertex); depth gets none.
"""

import torch

from dolphinfit.core.render.rasterize import Fragments, row_weights


def barycentrics(xy_px: torch.Tensor, faces: torch.Tensor, frags: Fragments) -> torch.Tensor:
    """(3, C) weights of the covered pixels in their faces, a row per corner (the layout the
    CPU runs fastest); xy_px: (T, V, 2)."""
    flat_idx = frags.frame * xy_px.shape[1] + faces.index_select(0, frags.face).T   # (3, C)
    corners = xy_px.reshape(-1, 2).index_select(0, flat_idx.reshape(-1))
    corners = corners.reshape(*flat_idx.shape, 2)
    centres = frags.pixel_centres(xy_px.dtype)
    return row_weights(corners[..., 0] - centres[:, 0], corners[..., 1] - centres[:, 1])


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
    """(C, D) Σ_k weights[k] · values[:, k] for weights (K, C) and values (C, K, D),
    written out over k: torch reduces a short middle axis several times slower."""
    total = weights[0, :, None] * values[:, 0]
    for k in range(1, weights.shape[0]):
        total = total + weights[k, :, None] * values[:, k]
    return total
