"""DIB-R soft silhouette: A = 1 − Π_j (1 − exp(−σ·d_j²)) at uncovered pixels, 1 where covered.

d_j is the distance from the pixel centre to primitive j, in pixels; σ and the box margin come
from :class:`RasterSettings` (softness rule there). The primitives considered at a pixel are
those whose box enlarged by the margin contains the pixel centre, at most k of them, the first
in index order. Two kinds of primitive (``RasterSettings.soft_primitives``):

- "faces", DIB-R's own: every face (front and back), d_j the distance to its boundary;
- "contour": the mesh's contour edges in that frame (core/render/contour.py), d_j the distance
  to the segment. Outside the silhouette the nearest point of the mesh lies on one of them, so
  the nearest term is the same; what differs is the crowd of faces seen edge-on along the
  outline, each adding a term, which makes the "faces" edge wider and costs 14× the pairs
  (140k against 10k a frame on a 232×200 crop of a 2.5 m animal at 20 m).

Only uncovered pixels are ever paired with primitives: with faces, a summed-area table first
drops those whose enlarged box holds no uncovered pixel (most faces; contour edges lie on the
outline, and the table would cost more than it saves); then, since in row-major order the uncovered
pixels of one box row form a contiguous run of the list of all uncovered pixels, a prefix count
over the uncovered map gives each (primitive, box row) segment its run directly.
"""

import torch

from dolphinfit.core.render.contour import MeshEdges, contour_edges, mesh_edges
from dolphinfit.core.render.pairs import ragged_chunks
from dolphinfit.core.render.rasterize import Fragments, face_boxes, face_corners, gather_corners
from dolphinfit.core.render.settings import RasterSettings

MAX_PROBABILITY = 1.0 - 1e-6   # clamp before log1p(−p) (rendering.md §11.8)
_TRIANGLE_EDGES = ([0, 1, 2], [1, 2, 0])   # boundary edge k runs from corner k to k + 1
_SEGMENT_EDGES = ([0], [1])


def soft_mask(xy_px: torch.Tensor, depth: torch.Tensor, faces: torch.Tensor,
              frags: Fragments, settings: RasterSettings,
              edges: MeshEdges | None = None) -> torch.Tensor:
    """(T, H, W) soft mask with gradients to ``xy_px`` (T, V, 2).

    ``edges``: the mesh's edges (contour mode), computed from ``faces`` when not given.
    """
    num_frames, height, width = frags.face_idx.shape
    if settings.soft_primitives == "contour":
        edges = edges if edges is not None else mesh_edges(faces)
        primitives = edges.verts
        frame, index = contour_edges(frags.front, depth, edges)
        corner_edges = _SEGMENT_EDGES
    else:
        primitives = faces
        frame, index = torch.nonzero((face_corners(depth, faces) > 0).all(-1), as_tuple=True)
        corner_edges = _TRIANGLE_EDGES
    corners = gather_corners(xy_px.detach(), primitives, frame, index)
    item, pixel = candidate_pairs(corners, frame, frags, settings)
    mask = frags.covered.to(xy_px.dtype).reshape(-1)
    if pixel.numel() == 0:
        return mask.reshape(num_frames, height, width)
    band, slot = torch.unique_consecutive(pixel, return_inverse=True)
    within = band % (height * width)
    band_xy = torch.stack([within % width, torch.div(within, width, rounding_mode="floor")],
                          dim=-1).to(xy_px.dtype)
    polygon = gather_corners(xy_px, primitives, frame[item], index[item])   # (P, C, 2)
    distance_sq = BoundaryDistanceSq.apply(polygon, band_xy[slot], *corner_edges)
    probability = torch.exp(-settings.sigma_px * distance_sq)
    log_keep = torch.log1p(-probability.clamp(max=MAX_PROBABILITY))
    total = torch.zeros(band.shape[0], dtype=xy_px.dtype, device=xy_px.device).index_add(
        0, slot, log_keep)
    mask = mask.index_put((band,), 1.0 - torch.exp(total))
    return mask.reshape(num_frames, height, width)


class BoundaryDistanceSq(torch.autograd.Function):
    """(P,) squared distance from points (P, 2) to polylines (P, C, 2) made of the edges
    ``starts[k]`` → ``ends[k]`` (a triangle's boundary, or one segment).

    The nearest point of an edge a→b is c = a + t(b − a), t clamped to [0, 1]; with r = p − c
    the gradient is ∂d²/∂a = −2(1 − t)·r and ∂d²/∂b = −2t·r on the nearest edge (envelope
    theorem: t is optimal, or clamped to a vertex), zero elsewhere. Fusing it saves the many
    intermediate tensors autograd would keep for the same expression.
    """

    @staticmethod
    def forward(ctx, corners: torch.Tensor, point: torch.Tensor, starts: list[int],
                ends: list[int]) -> torch.Tensor:
        # x and y as separate (P, C) tensors: reductions over a trailing size-2 axis are slow
        corner_x, corner_y = corners[..., 0].contiguous(), corners[..., 1].contiguous()
        start_x, start_y = corner_x[:, starts], corner_y[:, starts]
        edge_x = corner_x[:, ends] - start_x
        edge_y = corner_y[:, ends] - start_y
        rel_x = point[:, :1] - start_x
        rel_y = point[:, 1:] - start_y
        length_sq = (edge_x * edge_x + edge_y * edge_y).clamp(min=1e-30)
        along = ((rel_x * edge_x + rel_y * edge_y) / length_sq).clamp(0.0, 1.0)
        offset_x = rel_x - along * edge_x
        offset_y = rel_y - along * edge_y
        dist_sq, nearest = (offset_x * offset_x + offset_y * offset_y).min(dim=1)
        pick = nearest[:, None]
        ctx.num_corners = corners.shape[1]
        ctx.save_for_backward(torch.tensor(starts, device=nearest.device)[nearest],
                              torch.tensor(ends, device=nearest.device)[nearest],
                              along.gather(1, pick)[:, 0],
                              torch.cat([offset_x.gather(1, pick), offset_y.gather(1, pick)], 1))
        return dist_sq

    @staticmethod
    def backward(ctx, grad_dist_sq: torch.Tensor):
        start, end, along, offset = ctx.saved_tensors
        corners = torch.arange(ctx.num_corners, device=start.device)
        weight = ((corners == start[:, None]) * (1.0 - along)[:, None]
                  + (corners == end[:, None]) * along[:, None])                # (P, C)
        grad = (-2.0 * grad_dist_sq)[:, None, None] * weight[..., None] * offset[:, None, :]
        return grad.to(offset.dtype), None, None, None


def candidate_pairs(corners: torch.Tensor, frame: torch.Tensor, frags: Fragments,
                    settings: RasterSettings) -> tuple[torch.Tensor, torch.Tensor]:
    """(item, flat pixel) pairs of primitives (N, C, 2) in frames ``frame`` (N,) with the
    uncovered pixels of their enlarged boxes, sorted by pixel, k cap applied."""
    num_frames, height, width = frags.face_idx.shape
    boxes = face_boxes(corners, width, height, settings.margin_px)
    col_min, col_max, row_min, row_max = boxes
    near = (col_max >= col_min) & (row_max >= row_min)    # boxes not clamped away
    if settings.soft_primitives == "faces":
        # most faces lie inside the silhouette; contour edges lie on the outline, where nearly
        # every box holds uncovered pixels and the table would cost more than it saves
        near &= _uncovered_count(~frags.covered, frame, *boxes) > 0
    near = torch.nonzero(near, as_tuple=True)[0]
    frame = frame[near]
    col_min, col_max, row_min, row_max = (b[near] for b in boxes)
    rows = (row_max - row_min + 1).clamp(min=0)

    uncovered = ~frags.covered.reshape(-1)
    uncovered_pixels = torch.nonzero(uncovered, as_tuple=True)[0]
    # (a cumsum written into a slice of a zeroed tensor took ten times as long)
    before = torch.nn.functional.pad(torch.cumsum(uncovered, 0, dtype=torch.int64), (1, 0))

    parts = []
    for segments in ragged_chunks(rows, settings.max_pairs_per_chunk):
        item = segments.owner
        row_start = (frame[item] * height + row_min[item] + segments.local) * width
        start = before[row_start + col_min[item]]
        count = before[row_start + col_max[item] + 1] - start
        for run in ragged_chunks(count, settings.max_pairs_per_chunk):
            owner = item[run.owner]
            parts.append((owner, uncovered_pixels[start[run.owner] + run.local]))
    if not parts:
        empty = torch.zeros(0, dtype=torch.int64, device=frame.device)
        return empty, empty
    owner, pixel = (torch.cat(p) for p in zip(*parts))
    # a stable sort keeps each pixel's faces in index order; 32-bit keys sort twice as fast
    pixel32, order = torch.sort(pixel.to(torch.int32), stable=True)
    keep = _rank_within_runs(pixel32) < settings.max_faces_per_pixel
    return near[owner[order[keep]]], pixel32[keep].to(torch.int64)


def _uncovered_count(uncovered: torch.Tensor, frame: torch.Tensor, col_min: torch.Tensor,
                     col_max: torch.Tensor, row_min: torch.Tensor,
                     row_max: torch.Tensor) -> torch.Tensor:
    """Uncovered pixels inside each clamped, inclusive, non-empty box, from a summed-area
    table (an empty box gets a meaningless count)."""
    height, width = uncovered.shape[1:]
    table = torch.nn.functional.pad(uncovered.to(torch.int32).cumsum(1).cumsum(2), (1, 0, 1, 0))
    flat = table.reshape(-1)
    base = frame * ((height + 1) * (width + 1))
    top, bottom = row_min.clamp(max=height), row_max.clamp(min=-1) + 1
    left, right = col_min.clamp(max=width), col_max.clamp(min=-1) + 1
    return (flat[base + bottom * (width + 1) + right] - flat[base + top * (width + 1) + right]
            - flat[base + bottom * (width + 1) + left] + flat[base + top * (width + 1) + left])


def _rank_within_runs(values: torch.Tensor) -> torch.Tensor:
    """Position of each element within its run of equal, adjacent values."""
    position = torch.arange(values.shape[0], device=values.device)
    run_start = torch.ones_like(values, dtype=torch.bool)
    run_start[1:] = values[1:] != values[:-1]
    return position - torch.cummax(torch.where(run_start, position, 0), dim=0).values
