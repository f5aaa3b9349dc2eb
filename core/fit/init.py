"""Placing the model from the masks before any optimisation (DESIGN.md §6).

Per frame: the mask's centroid, unprojected to the plane at the initial depth, gives the body
centre; its principal axis gives the heading up to 180°, made continuous over time so that one
global flip (tried both ways by the engine) resolves it; its extent along the axis gives the
length. The template's root joint is not the centre of its silhouette, so the root is placed
at the centroid minus the template's own centroid offset, rotated and scaled.
"""

import math
from dataclasses import dataclass

import numpy as np
import torch

from dolphinfit.core.fit.data import FitData
from dolphinfit.core.measure.mesh import body_length
from dolphinfit.core.model.model import DolphinModel

# Bending, pitch and dives only ever shorten the silhouette: the length comes from the upper
# end of the per-frame extents, not their median.
EXTENT_PERCENTILE = 80.0


@dataclass(frozen=True)
class InitialState:
    """Per-frame heading and root position, and the overall log scale."""

    heading_rad: np.ndarray   # (T,) yaw of the body axis (rostrum direction) from world +x
    centre_xy: np.ndarray     # (T, 2) silhouette centroid on the water plane, metres
    log_scale: float          # log(estimated length / template length)


def silhouette_centroid_offset(model: DolphinModel) -> np.ndarray:
    """(2,) area centroid of the template seen from above, relative to the root joint (x, y)."""
    verts = model.rest_verts.double()
    v0, v1, v2 = (verts[model.faces[:, k]] for k in range(3))
    area_up = 0.5 * torch.linalg.cross(v1 - v0, v2 - v0, dim=-1)[:, 2].clamp(min=0.0)
    centre = (v0 + v1 + v2)[:, :2] / 3.0
    offset = (centre * area_up[:, None]).sum(0) / area_up.sum()
    return offset.cpu().numpy() - model.rest_joints[0, :2].double().cpu().numpy()


def template_length_m(model: DolphinModel) -> float:
    """Body length of the unshaped template, metres."""
    return float(body_length(model.rest_verts, model.rostrum_idx, model.notch_idx))


def template_extent_ratio(model: DolphinModel) -> float:
    """Top-view extent along the body (rostrum to fluke tips) / body length."""
    x = model.rest_verts[:, 0]
    return float(x.max() - x.min()) / template_length_m(model)


def initial_state(data: FitData, model: DolphinModel, depth_m: float) -> InitialState:
    """Centroid, continuous heading and length estimate from the masks of ``data``."""
    gsd = (data.camera.altitude_m.double() + depth_m) / data.camera.intrinsics.focal_px
    centres_px, headings, extents_m = [], [], []
    masks = data.masks.cpu().numpy()
    for t in range(data.num_frames):
        rows, cols = np.nonzero(masks[t] > 0.5)
        points = np.stack([cols + float(data.viewport.x0_px[t]),
                           rows + float(data.viewport.y0_px[t])], 1).astype(np.float64)
        centre = points.mean(0)
        _, _, axes = np.linalg.svd(points - centre, full_matrices=False)
        axis = axes[0]
        along = (points - centre) @ axis
        centres_px.append(centre)
        headings.append(math.atan2(-axis[1], axis[0]))   # image down is world −y
        extents_m.append((along.max() - along.min() + 1.0) * float(gsd[t]))
    centre_px = torch.as_tensor(np.asarray(centres_px))[:, None, :]
    plane = torch.full((data.num_frames,), -depth_m, dtype=torch.float64)
    world = unproject_frames(data, centre_px, plane)
    length_m = float(np.percentile(extents_m, EXTENT_PERCENTILE)) / template_extent_ratio(model)
    return InitialState(heading_rad=_continuous(np.asarray(headings)),
                        centre_xy=world[:, 0, :2].numpy(),
                        log_scale=math.log(length_m / template_length_m(model)))


def unproject_frames(data: FitData, xy_px: torch.Tensor, plane_z: torch.Tensor) -> torch.Tensor:
    """World points (T, N, 3) of full-frame pixels (T, N, 2) on planes z = plane_z (T,)."""
    camera = data.camera
    double = type(camera)(camera.intrinsics, camera.altitude_m.double(), camera.refraction,
                          camera.n_water)
    return double.unproject(xy_px.double(), plane_z)


def root_positions(state: InitialState, heading: np.ndarray, offset_xy: np.ndarray,
                   depth_m: float) -> np.ndarray:
    """(T, 3) root joint positions that put the silhouette centroid at the mask centroid."""
    scale = math.exp(state.log_scale)
    cos, sin = np.cos(heading), np.sin(heading)
    rotated = np.stack([cos * offset_xy[0] - sin * offset_xy[1],
                        sin * offset_xy[0] + cos * offset_xy[1]], 1) * scale
    xy = state.centre_xy - rotated
    return np.column_stack([xy, np.full(len(xy), -depth_m)])


def _continuous(heading: np.ndarray) -> np.ndarray:
    """Headings (defined modulo π) made continuous: each within ±90° of the previous one."""
    out = heading.copy()
    for t in range(1, len(out)):
        step = (out[t] - out[t - 1] + math.pi / 2) % math.pi - math.pi / 2
        out[t] = out[t - 1] + step
    return out
