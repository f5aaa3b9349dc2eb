"""The contour of a posed mesh and the soft silhouette measured to it."""

import numpy as np
import torch
import trimesh

from dolphinfit.core.render.contour import contour_edges, mesh_edges
from dolphinfit.core.render.rasterize import gather_corners, rasterize
from dolphinfit.core.render.render import project_to_viewport
from dolphinfit.core.render.settings import RasterSettings, Viewport
from dolphinfit.core.render.soft_mask import (
    _SEGMENT_EDGES, _TRIANGLE_EDGES, BoundaryDistanceSq, soft_mask,
)

from .scenes import camera, moved, two_ellipsoids

WIDTH, HEIGHT = 64, 48


def _projected():
    verts, faces, _ = two_ellipsoids()
    verts_t = moved(verts, [(0.05, -0.1, 0.0)], yaw_rad=0.4)
    cam = camera(WIDTH, HEIGHT, [1.6])
    xy, depth = project_to_viewport(verts_t, cam, Viewport.full_frame(cam.intrinsics, 1))
    return xy, depth, faces


def test_mesh_edges_of_a_closed_mesh_match_trimesh():
    """Each undirected edge once, two faces each, and every face corner maps to its edge."""
    sphere = trimesh.creation.icosphere(subdivisions=2)
    faces = torch.as_tensor(sphere.faces, dtype=torch.int64)
    edges = mesh_edges(faces)
    assert edges.verts.shape[0] == len(sphere.edges_unique) == 3 * len(faces) // 2
    assert bool((edges.num_faces == 2).all())
    corner_start = faces.reshape(-1)
    corner_end = faces.roll(-1, dims=1).reshape(-1)
    pair = edges.verts[edges.of_corner]
    assert torch.equal(pair.amin(1), torch.minimum(corner_start, corner_end))
    assert torch.equal(pair.amax(1), torch.maximum(corner_start, corner_end))


def test_contour_of_closed_meshes_is_made_of_closed_loops():
    """Every vertex on the contour of two ellipsoids meets an even number of contour edges,
    and the contour holds far fewer edges than the mesh."""
    xy, depth, faces = _projected()
    edges = mesh_edges(faces)
    frags = rasterize(xy, depth, faces, HEIGHT, WIDTH, 10**6)
    frame, index = contour_edges(frags.front, depth, edges)
    ends = edges.verts[index].reshape(-1)
    degree = torch.bincount(ends, minlength=xy.shape[1])
    assert len(index) >= 16
    assert len(index) < edges.verts.shape[0] / 3
    assert bool((degree % 2 == 0).all())
    assert bool((frame == 0).all())


def test_nearest_contour_edge_is_the_nearest_point_of_the_mesh():
    """Outside the silhouette the distance to the nearest contour edge equals the distance to
    the nearest face boundary, so both soft masks share their strongest term."""
    xy, depth, faces = _projected()
    frags = rasterize(xy, depth, faces, HEIGHT, WIDTH, 10**6)
    rows, cols = torch.nonzero(~frags.covered[0], as_tuple=True)
    points = torch.stack([cols, rows], -1).to(xy.dtype)
    edges = mesh_edges(faces)
    _, index = contour_edges(frags.front, depth, edges)

    def nearest(corners, corner_edges):
        num_points, num = points.shape[0], corners.shape[0]
        repeated = corners[None].expand(num_points, -1, -1, -1).reshape(-1, *corners.shape[1:])
        dist = BoundaryDistanceSq.apply(repeated, points.repeat_interleave(num, 0),
                                        *corner_edges)
        return dist.reshape(num_points, num).amin(1)

    zero = torch.zeros(1, dtype=torch.int64)
    contour = gather_corners(xy, edges.verts, zero.expand(len(index)), index)
    all_faces = gather_corners(xy, faces, zero.expand(len(faces)), torch.arange(len(faces)))
    torch.testing.assert_close(nearest(contour, _SEGMENT_EDGES),
                               nearest(all_faces, _TRIANGLE_EDGES), rtol=1e-9, atol=1e-9)


def test_contour_soft_mask_is_narrower_than_the_face_one():
    """Both are 1 on covered pixels; outside, the contour one never exceeds the face one on
    these ellipsoids (no face carries two contour edges, so each contour term has a face term
    at most as far), yet still reaches above 0.5 beside the outline."""
    xy, depth, faces = _projected()
    frags = rasterize(xy, depth, faces, HEIGHT, WIDTH, 10**6)
    contour = soft_mask(xy, depth, faces, frags, RasterSettings())
    every_face = soft_mask(xy, depth, faces, frags, RasterSettings(soft_primitives="faces"))
    covered = frags.covered
    assert bool((contour[covered] == 1).all()) and bool((every_face[covered] == 1).all())
    assert bool((contour[~covered] <= every_face[~covered] + 1e-12).all())
    assert float(contour[~covered].max()) > 0.5
    band = np.count_nonzero((contour > 0.01).numpy() & ~covered.numpy())
    assert band > 30
