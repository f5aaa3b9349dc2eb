"""DIB-R soft silhouette: A = 1 − Π_j (1 − exp(−σ·d_j²)) at uncovered pixels, 1 where covered.

d_j is the distance from the pixel centre to face j's boundary (nearest edge or vertex), in
pixels; σ and the box margin come from :class:`RasterSettings` (softness rule there). The faces
considered at a pixel are all faces (front and back) whose box enlarged by the margin contains
the pixel centre, at most k of them, the first in face-index order. Only faces whose enlarged
box holds an uncovered pixel are enumerated (a summed-area table tells), so interior faces cost
nothing.
"""

import torch

from core.render.pairs import box_pair_chunks
from core.render.rasterize import Fragments, face_boxes
from core.render.settings import RasterSettings

MAX_PROBABILITY = 1.0 - 1e-6   # clamp before log1p(−p) (rendering.md §11.8)


def soft_mask(xy_px: torch.Tensor, depth: torch.Tensor, faces: torch.Tensor,
              frags: Fragments, settings: RasterSettings) -> torch.Tensor:
    """(T, H, W) soft mask with gradients to ``xy_px`` (T, V, 2)."""
    num_frames, height, width = frags.face_idx.shape
    frame, face, pixel = _candidate_pairs(xy_px.detach(), depth, faces, frags, settings)
    if pixel.numel() == 0:
        return frags.covered.to(xy_px.dtype)
    tri = xy_px[frame[:, None], faces[face]]                       # (P, 3, 2)
    within = pixel % (height * width)
    point = torch.stack([within % width, torch.div(within, width, rounding_mode="floor")],
                        dim=-1).to(xy_px.dtype)
    probability = torch.exp(-settings.sigma_px * boundary_distance_sq(tri, point))
    log_keep = torch.log1p(-probability.clamp(max=MAX_PROBABILITY))
    total = torch.zeros(num_frames * height * width, dtype=xy_px.dtype).index_add(0, pixel,
                                                                                  log_keep)
    mask = 1.0 - torch.exp(total).reshape(num_frames, height, width)
    return torch.where(frags.covered, torch.ones_like(mask), mask)


def boundary_distance_sq(tri: torch.Tensor, point: torch.Tensor) -> torch.Tensor:
    """(P,) squared distance from ``point`` (P, 2) to the boundary of ``tri`` (P, 3, 2)."""
    start = tri
    edge = torch.roll(tri, shifts=-1, dims=-2) - tri               # (P, 3, 2)
    rel = point[:, None, :] - start
    length_sq = (edge * edge).sum(-1).clamp(min=1e-30)
    along = ((rel * edge).sum(-1) / length_sq).clamp(0.0, 1.0)
    offset = rel - along[..., None] * edge
    return (offset * offset).sum(-1).amin(-1)


def _candidate_pairs(xy_px: torch.Tensor, depth: torch.Tensor, faces: torch.Tensor,
                     frags: Fragments, settings: RasterSettings) -> tuple[torch.Tensor, ...]:
    """(frame, face, flat pixel) of the pairs that enter the product, k cap applied."""
    num_frames, height, width = frags.face_idx.shape
    tri = xy_px[:, faces]                                          # (T, F, 3, 2)
    frame, face = torch.nonzero((depth[:, faces] > 0).all(-1), as_tuple=True)
    boxes = face_boxes(tri[frame, face], width, height, settings.margin_px)
    has_uncovered = _uncovered_count(~frags.covered, frame, *boxes) > 0
    frame, face = frame[has_uncovered], face[has_uncovered]
    boxes = tuple(b[has_uncovered] for b in boxes)

    uncovered = ~frags.covered.reshape(-1)
    parts = []
    for pairs in box_pair_chunks(*boxes, settings.max_pairs_per_chunk):
        pixel = (frame[pairs.owner] * height * width + pairs.row * width + pairs.col)
        keep = uncovered[pixel]
        parts.append((frame[pairs.owner][keep], face[pairs.owner][keep], pixel[keep]))
    if not parts:
        empty = torch.zeros(0, dtype=torch.int64)
        return empty, empty, empty
    frame, face, pixel = (torch.cat(p) for p in zip(*parts))
    return _first_k_per_pixel(frame, face, pixel, settings.max_faces_per_pixel)


def _uncovered_count(uncovered: torch.Tensor, frame: torch.Tensor, col_min: torch.Tensor,
                     col_max: torch.Tensor, row_min: torch.Tensor,
                     row_max: torch.Tensor) -> torch.Tensor:
    """Uncovered pixels inside each (clamped, inclusive) box, from a summed-area table."""
    table = torch.nn.functional.pad(uncovered.to(torch.int64).cumsum(1).cumsum(2), (1, 0, 1, 0))
    height, width = uncovered.shape[1:]
    col_min, row_min = col_min.clamp(max=width), row_min.clamp(max=height)
    col_max, row_max = col_max.clamp(min=-1), row_max.clamp(min=-1)
    count = (table[frame, row_max + 1, col_max + 1] - table[frame, row_min, col_max + 1]
             - table[frame, row_max + 1, col_min] + table[frame, row_min, col_min])
    return torch.where((col_max >= col_min) & (row_max >= row_min), count, 0)


def _first_k_per_pixel(frame: torch.Tensor, face: torch.Tensor, pixel: torch.Tensor,
                       k: int) -> tuple[torch.Tensor, ...]:
    """Keep at most ``k`` pairs per pixel, those of the lowest face indices."""
    if pixel.numel() == 0 or int(torch.bincount(pixel).max()) <= k:
        return frame, face, pixel
    order = torch.argsort(pixel * (int(face.max()) + 1) + face)
    frame, face, pixel = frame[order], face[order], pixel[order]
    run_start = torch.ones_like(pixel, dtype=torch.bool)
    run_start[1:] = pixel[1:] != pixel[:-1]
    position = torch.arange(pixel.shape[0])
    first = torch.cummax(torch.where(run_start, position, 0), dim=0).values
    keep = position - first < k
    return frame[keep], face[keep], pixel[keep]
