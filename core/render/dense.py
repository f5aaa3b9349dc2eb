"""Dense brute-force renderer: every pixel against every face, to check the sparse one.

Kept in the library on purpose (as pytorch3d keeps its Python rasterizer): the tests compare
results and gradients against it, and ``dolphinfit bench render`` times it side by side.

Same semantics as core/render (front-most front face by screen-space depth, ties to the larger
face index; DIB-R soft mask over the first k faces, or contour edges, in index order whose
margin-enlarged box holds the pixel; foreground interpolated at the winner), but no boxes,
pair lists, chunks, summed-area tables or sorting: only dense (pixels × faces) tensors, so
memory grows with pixels × faces (and the contour's search with faces²). The barycentric
formula and the pointwise shading functions are shared.
"""

import torch

from dolphinfit.core.render.rasterize import cross2, edge_weights
from dolphinfit.core.render.render import Appearance
from dolphinfit.core.render.settings import RasterSettings
from dolphinfit.core.render.shade import (
    sample_texture, sg_irradiance, vertex_normals, water_filter,
)


def pixel_grid(height: int, width: int, dtype: torch.dtype) -> torch.Tensor:
    """(H·W, 2) pixel centres (u, v) in row-major order."""
    rows, cols = torch.meshgrid(torch.arange(height), torch.arange(width), indexing="ij")
    return torch.stack([cols.reshape(-1), rows.reshape(-1)], -1).to(dtype)


def dense_face_index(tri: torch.Tensor, tri_depth: torch.Tensor, points: torch.Tensor):
    """(H·W,) front-most face and (H·W, F, 3) weights for one frame."""
    weights = edge_weights(tri[None].detach(), points[:, None])             # (HW, F, 3)
    area2 = cross2(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]).detach()
    valid = (area2 < 0) & (tri_depth > 0).all(-1)
    inside = (weights >= 0).all(-1) & valid[None]
    depth = torch.where(inside, (weights * tri_depth[None]).sum(-1), torch.inf)
    nearest = inside & (depth == depth.min(dim=1, keepdim=True).values)
    face_ids = torch.arange(tri.shape[0]).expand_as(nearest)
    return torch.where(nearest, face_ids, -1).max(dim=1).values


def dense_contour(tri: torch.Tensor, tri_depth: torch.Tensor,
                  faces: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """(N, 2, 2) corners and (N, 2) depths of one frame's contour edges, in the order of
    their (smaller, larger) vertex indices: every face corner's edge against every face."""
    starts, ends = faces.reshape(-1), faces.roll(-1, dims=1).reshape(-1)           # (3F,)
    sharing = ((faces[None] == starts[:, None, None]).any(-1)
               & (faces[None] == ends[:, None, None]).any(-1))                     # (3F, F)
    front = cross2(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]).detach() < 0
    num_front = (sharing & front[None]).sum(1)
    num_faces = sharing.sum(1)
    owner = torch.arange(faces.shape[0]).repeat_interleave(3)
    first = torch.where(sharing, torch.arange(faces.shape[0])[None], faces.shape[0]).amin(1)
    corner_xy = tri.reshape(-1, 2)
    corner_depth = tri_depth.reshape(-1)
    end_corner = torch.arange(3 * faces.shape[0]).reshape(-1, 3).roll(-1, dims=1).reshape(-1)
    keep = ((first == owner) & (((num_front > 0) & (num_front < num_faces)) | (num_faces == 1))
            & (corner_depth > 0) & (corner_depth[end_corner] > 0))
    low, high = torch.minimum(starts, ends), torch.maximum(starts, ends)
    order = torch.argsort(low * (int(faces.max()) + 1) + high)
    order = order[keep[order]]
    return (torch.stack([corner_xy[order], corner_xy[end_corner[order]]], 1),
            torch.stack([corner_depth[order], corner_depth[end_corner[order]]], 1))


def dense_soft_mask(tri: torch.Tensor, tri_depth: torch.Tensor, points: torch.Tensor,
                    covered: torch.Tensor, settings: RasterSettings,
                    faces: torch.Tensor) -> torch.Tensor:
    """(H·W,) soft mask of one frame: explicit product over the first k candidate
    primitives (faces, or contour edges, as ``settings.soft_primitives`` says)."""
    if settings.soft_primitives == "contour":
        tri, tri_depth = dense_contour(tri, tri_depth, faces)
    margin = settings.margin_px
    lo, hi = tri.detach().amin(1), tri.detach().amax(1)                     # (N, 2)
    in_box = ((points[:, None] >= lo[None] - margin) & (points[:, None] < hi[None] + margin)).all(-1)
    candidate = in_box & (tri_depth > 0).all(-1)[None] & ~covered[:, None]
    candidate = candidate & (torch.cumsum(candidate.to(torch.int64), dim=1) <= settings.max_faces_per_pixel)
    dist_sq = torch.full(candidate.shape, torch.inf, dtype=tri.dtype)
    corners = tri.shape[1]
    for k in range(corners if corners > 2 else 1):
        a, b = tri[:, k], tri[:, (k + 1) % corners]
        ab = b - a
        ap = points[:, None] - a[None]
        t = ((ap * ab[None]).sum(-1) / (ab * ab).sum(-1)[None]).clamp(0, 1)
        foot = a[None] + t[..., None] * ab[None]
        dist_sq = torch.minimum(dist_sq, ((points[:, None] - foot) ** 2).sum(-1))
    prob = torch.exp(-settings.sigma_px * dist_sq).clamp(max=1 - 1e-6)
    keep = torch.where(candidate, 1 - prob, torch.ones_like(prob))
    soft = 1 - torch.prod(keep, dim=1)
    return torch.where(covered, torch.ones_like(soft), soft)


def dense_render(verts_world, xy_px, depth, faces, appearance: Appearance, height: int,
                 width: int, settings: RasterSettings):
    """(face_idx (T, H, W), soft mask (T, H, W), rgb (T, H, W, 3)) by brute force."""
    points = pixel_grid(height, width, xy_px.dtype)
    normals = vertex_normals(verts_world, faces)
    albedo = appearance.albedo if appearance.albedo.dim() == 3 else appearance.albedo[..., None]
    face_maps, soft_maps, rgb_maps = [], [], []
    for t in range(xy_px.shape[0]):
        tri, tri_depth = xy_px[t][faces], depth[t][faces]
        face_idx = dense_face_index(tri, tri_depth, points)
        covered = face_idx >= 0
        soft_maps.append(dense_soft_mask(tri, tri_depth, points, covered, settings, faces))
        weights = edge_weights(tri[None], points[:, None])                   # (HW, F, 3) grad
        is_winner = torch.arange(faces.shape[0])[None] == face_idx[:, None]  # (HW, F)
        # where, not a product: degenerate faces have non-finite weights, and NaN·0 is NaN
        w = torch.where(is_winner[..., None], weights, 0.0).sum(1)           # (HW, 3)
        onehot = is_winner.to(xy_px.dtype)[..., None, None]

        def at_winner(corner_values):                                        # (F, 3, D)
            return (w[..., None] * (onehot * corner_values[None]).sum(1)).sum(1)

        uv = at_winner(appearance.face_uvs)
        normal = at_winner(normals[t][faces])
        normal = normal / torch.linalg.vector_norm(normal, dim=-1, keepdim=True).clamp(min=1e-20)
        z = at_winner(verts_world[t][faces][..., 2:])[:, 0]
        colour = sample_texture(albedo, uv) / torch.pi * sg_irradiance(normal, appearance.light)
        colour = water_filter(colour, z, appearance.f_water) * covered[:, None]
        face_maps.append(face_idx.reshape(height, width))
        soft_maps[-1] = soft_maps[-1].reshape(height, width)
        rgb_maps.append(colour.reshape(height, width, 3))
    return torch.stack(face_maps), torch.stack(soft_maps), torch.stack(rgb_maps)
