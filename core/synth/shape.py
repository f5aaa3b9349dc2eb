"""The synthetic animal's shape: random part scales, plus shape the fit cannot express.

``random_betas`` draws per-part log scales and rescales uniformly to the requested length.
``warp_profiles`` changes the template's width and height profiles by smooth random factors
along the body (outside the span of per-part scaling; the profile field of the fit follows
them). ``draw_hw`` draws an animal's height/width ratios from an HW table (for
``core.model.sections.reshape_sections``). ``subdivide`` gives a finer, smoother
(Loop-subdivided) template with skinning weights and UVs carried over.
"""

import math
from dataclasses import replace

import numpy as np
import torch
import trimesh

from dolphinfit.core.measure.hw_ratios import HWRatios
from dolphinfit.core.measure.mesh import body_length
from dolphinfit.core.measure.stations import STATION_FRACTIONS
from dolphinfit.core.model.model import NUM_SHAPE_PARAMS, DolphinModel
from dolphinfit.core.model.sections import NUM_TABLE_STATIONS
from dolphinfit.core.model.template import Template

WARP_COMPONENTS = 3        # sine components along the body
WARP_AMPLITUDE = 0.05      # each component's amplitude, relative width/height change


def random_betas(model: DolphinModel, length_m: float, shape_sd: float,
                 rng: np.random.Generator, tie_heights: bool = False) -> torch.Tensor:
    """(M, 4) log part scales with SD ``shape_sd``, rescaled to body length ``length_m``;
    with ``tie_heights`` each part's z scale is its y scale (its height/width ratio stays)."""
    draws = rng.normal(0.0, shape_sd, size=(model.num_groups, NUM_SHAPE_PARAMS))
    if tie_heights:
        draws[:, 3] = draws[:, 2]
    betas = torch.tensor(draws, dtype=model.rest_verts.dtype)
    rest = model.forward_rest(betas)[0]
    current = body_length(rest, model.rostrum_idx, model.notch_idx)
    betas[:, 0] += torch.log(length_m / current)
    return betas


def warp_profiles(template: Template, rng: np.random.Generator,
                  tie_heights: bool = False) -> Template:
    """The template with widths and heights scaled by smooth random factors along the body.

    Each vertex moves away from (or towards) the body axis: its y by 1 + a_w(t) and its z by
    1 + a_h(t) (by 1 + a_w(t) too with ``tie_heights``, so height/width ratios stay), with t
    its position along the body; both factors are 1 at the rostrum tip and the fluke notch,
    so length is kept.
    """
    x = template.verts[:, 0]
    t = np.clip((x[template.rostrum_idx] - x) / template.length_m, 0.0, 1.0)
    envelope = np.sin(math.pi * t)

    def factor() -> np.ndarray:
        phases = rng.uniform(0, 2 * math.pi, WARP_COMPONENTS)
        amplitudes = rng.uniform(-WARP_AMPLITUDE, WARP_AMPLITUDE, WARP_COMPONENTS)
        waves = sum(a * np.sin(math.pi * (k + 1) * t + p)
                    for k, (a, p) in enumerate(zip(amplitudes, phases)))
        return 1.0 + envelope * waves

    verts = template.verts.copy()
    width_factor, height_factor = factor(), factor()   # both drawn: the same stream either way
    verts[:, 1] *= width_factor
    verts[:, 2] *= width_factor if tie_heights else height_factor
    return replace(template, verts=verts)


def draw_hw(table: HWRatios, rng: np.random.Generator) -> np.ndarray:
    """(17,) HW ratios at the 5–85 % stations for one animal.

    Each ratio lies off the table's mean by its SD times a smooth standard-normal field along
    the body (half the variance shared by every station, half in two slow waves), so
    neighbouring stations move together as a real animal's would.
    """
    ratios, sd = table.ratios[:NUM_TABLE_STATIONS], table.sd[:NUM_TABLE_STATIONS]
    t = STATION_FRACTIONS[:NUM_TABLE_STATIONS]
    common = rng.normal()
    waves = sum(rng.normal() * np.sin(math.pi * (k + 1) * t + rng.uniform(0, 2 * math.pi))
                for k in range(2))
    field = math.sqrt(0.5) * (common + waves)   # waves: variance 1 on average over phases
    return np.maximum(ratios + sd * field, 0.5)


def subdivide(template: Template) -> Template:
    """One Loop subdivision: 4× the faces, a smoother surface; attributes carried over.

    New vertices take the skinning weights of their closest point on the original surface;
    each new face takes its corner UVs from the original face under its centroid, so faces
    never straddle a UV seam. Loop subdivision keeps the original vertices first (moved by
    the smoothing), so landmark, station-ring and fin indices stay valid.
    """
    verts, faces = trimesh.remesh.subdivide_loop(template.verts, template.faces, iterations=1)
    original = trimesh.Trimesh(template.verts, template.faces, process=False)
    _, _, parent_of_vertex = trimesh.proximity.closest_point(original, verts)
    vertex_bary = trimesh.triangles.points_to_barycentric(
        original.triangles[parent_of_vertex], verts)
    weights = np.einsum("vk,vkj->vj", vertex_bary,
                        template.skin_weights[template.faces[parent_of_vertex]])

    _, _, parent_of_face = trimesh.proximity.closest_point(original, verts[faces].mean(1))
    corner_bary = trimesh.triangles.points_to_barycentric(
        np.repeat(original.triangles[parent_of_face], 3, axis=0), verts[faces].reshape(-1, 3))
    parent_uvs = template.uvs[template.face_uvs_idx[parent_of_face]]          # (F', 3, 2)
    corner_uvs = np.einsum("fck,fkd->fcd", corner_bary.reshape(-1, 3, 3), parent_uvs)
    uvs, uv_idx = np.unique(np.clip(corner_uvs, 0.0, 1.0).reshape(-1, 2), axis=0,
                            return_inverse=True)
    return replace(template, verts=verts, faces=faces, uvs=uvs,
                   face_uvs_idx=uv_idx.reshape(-1, 3),
                   skin_weights=weights / weights.sum(1, keepdims=True))
