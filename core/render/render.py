"""The full render of posed meshes through a nadir camera into per-frame viewports."""

from dataclasses import dataclass
from functools import cached_property

import torch

from dolphinfit.core.camera import NadirCamera
from dolphinfit.core.render.contour import MeshEdges
from dolphinfit.core.render.interpolate import (
    barycentrics, interpolate_corner_values, interpolate_vertex_values,
)
from dolphinfit.core.render.rasterize import Fragments, rasterize
from dolphinfit.core.render.settings import RasterSettings, Viewport
from dolphinfit.core.render.shade import (
    SGLight, sample_texture, sg_irradiance, vertex_normals, water_filter,
)
from dolphinfit.core.render.soft_mask import soft_mask


@dataclass(frozen=True, eq=False)
class Appearance:
    """What the surface looks like: texture on the UV map, light, and water."""

    albedo: torch.Tensor      # (Ht, Wt) or (Ht, Wt, C) in [0, 1]; grayscale in the paper
    face_uvs: torch.Tensor    # (F, 3, 2) UV of each face corner (v from the top row)
    light: SGLight
    f_water: torch.Tensor     # (3,) per-channel attenuation per metre of depth, in [0, 1]


@dataclass(frozen=True, eq=False)
class RenderOutput:
    """Per-frame images of the viewport; shapes (T, H, W, …). Colour and height are kept at
    the covered pixels; their whole images are built when first read (the fit never does).
    A render without shading has neither."""

    soft_mask: torch.Tensor     # (T, H, W) DIB-R soft silhouette
    coverage: torch.Tensor      # (T, H, W) bool hard coverage
    face_idx: torch.Tensor      # (T, H, W) int64 front face, −1 where uncovered
    pixel: torch.Tensor         # (C,) int64 flat index t·H·W + row·W + col of covered pixels
    pixel_rgb: torch.Tensor | None      # (C, 3) their shaded, water-filtered colour
    pixel_height: torch.Tensor | None   # (C,) their world height of the surface (z), metres

    @cached_property
    def rgb(self) -> torch.Tensor:
        """(T, H, W, 3) colour, 0 where uncovered."""
        return self._image(self.pixel_rgb)

    @cached_property
    def height_m(self) -> torch.Tensor:
        """(T, H, W) world height of the surface, 0 where uncovered."""
        return self._image(self.pixel_height)

    def _image(self, values: torch.Tensor | None) -> torch.Tensor:
        if values is None:
            raise ValueError("a render without shading has no colour or height image")
        shape = self.face_idx.shape
        flat = torch.zeros(shape.numel(), *values.shape[1:], dtype=values.dtype,
                           device=values.device)
        return flat.index_put((self.pixel,), values).reshape(*shape, *values.shape[1:])


def project_to_viewport(verts_world: torch.Tensor, camera: NadirCamera,
                        viewport: Viewport) -> tuple[torch.Tensor, torch.Tensor]:
    """Viewport pixels (T, V, 2) and depth below the camera (T, V) of world vertices."""
    xy = camera.project(verts_world)
    offset = torch.stack([viewport.x0_px, viewport.y0_px], dim=-1).to(xy.dtype)[:, None, :]
    depth = camera.altitude_m.to(verts_world.dtype)[:, None] - verts_world[..., 2]
    return xy - offset, depth


def render(verts_world: torch.Tensor, faces: torch.Tensor, appearance: Appearance,
           camera: NadirCamera, viewport: Viewport,
           settings: RasterSettings = RasterSettings(),
           edges: MeshEdges | None = None, shade: bool = True) -> RenderOutput:
    """Render meshes (T, V, 3) (world frame, metres) into the viewports of ``camera``; without
    ``shade`` the silhouette only (a fifth to a third less work where no colour is read).

    ``edges``: ``mesh_edges(faces)``, to save recomputing it in every call.
    """
    xy_px, depth = project_to_viewport(verts_world, camera, viewport)
    frags = rasterize(xy_px, depth, faces, viewport.height_px, viewport.width_px,
                      settings.max_pairs_per_chunk)
    silhouette = soft_mask(xy_px, depth, faces, frags, settings, edges)
    colour, height = (shade_fragments(verts_world, xy_px, faces, frags, appearance) if shade
                      else (None, None))
    return RenderOutput(soft_mask=silhouette, coverage=frags.covered, face_idx=frags.face_idx,
                        pixel=frags.pixel, pixel_rgb=colour, pixel_height=height)


def shade_fragments(verts_world: torch.Tensor, xy_px: torch.Tensor, faces: torch.Tensor,
                    frags: Fragments, appearance: Appearance) -> tuple[torch.Tensor, torch.Tensor]:
    """(C, 3) colour and (C,) world height at the covered pixels."""
    weights = barycentrics(xy_px, faces, frags)
    uv = interpolate_corner_values(appearance.face_uvs, frags, weights)
    normals = interpolate_vertex_values(vertex_normals(verts_world, faces), faces, frags, weights)
    normals = normals / torch.linalg.vector_norm(normals, dim=-1, keepdim=True).clamp(min=1e-20)
    height = interpolate_vertex_values(verts_world[..., 2:], faces, frags, weights)[:, 0]
    albedo = appearance.albedo if appearance.albedo.dim() == 3 else appearance.albedo[..., None]
    radiance = sample_texture(albedo, uv) / torch.pi * sg_irradiance(normals, appearance.light)
    return water_filter(radiance, height, appearance.f_water), height
