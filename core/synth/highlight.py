"""Sun highlights on the wet skin of the parts above the water (Blinn–Phong, synth only).

Wet dolphin skin out of the water mirrors the sun: a sharp highlight where the surface normal
meets the half vector between the sun and the camera, inside a broader sheen. Normals are
interpolated per pixel (the lobe is narrower than the mesh's facets); submerged skin gets none
(the water surface, not the skin, reflects there).
"""

import torch

from dolphinfit.core.camera import NadirCamera
from dolphinfit.core.render.interpolate import barycentrics, interpolate_vertex_values
from dolphinfit.core.render.rasterize import rasterize
from dolphinfit.core.render.render import project_to_viewport
from dolphinfit.core.render.settings import RasterSettings, Viewport
from dolphinfit.core.render.shade import vertex_normals

SHARP_LOBE = 300.0      # exp(κ(n·h − 1)) of the specular spot
SHEEN_LOBE = 40.0       # … of the broad wet sheen
SHEEN_WEIGHT = 0.15
WET_FILM_M = 0.03       # highlights fade over this depth below the surface


def wet_highlight(verts_world: torch.Tensor, faces: torch.Tensor, camera: NadirCamera,
                  viewport: Viewport, sun: torch.Tensor, strength: float) -> torch.Tensor:
    """(H, W) highlight radiance over the viewport of one posed mesh (1, V, 3)."""
    xy, depth = project_to_viewport(verts_world, camera, viewport)
    frags = rasterize(xy, depth, faces, viewport.height_px, viewport.width_px,
                      RasterSettings().max_pairs_per_chunk)
    weights = barycentrics(xy, faces, frags)
    normals = interpolate_vertex_values(vertex_normals(verts_world, faces), faces, frags, weights)
    normals = normals / torch.linalg.vector_norm(normals, dim=-1, keepdim=True).clamp(min=1e-20)
    points = interpolate_vertex_values(verts_world, faces, frags, weights)
    eye = torch.zeros(3, dtype=points.dtype)
    eye[2] = camera.altitude_m[0]
    to_camera = eye - points
    halfway = to_camera / torch.linalg.vector_norm(to_camera, dim=-1, keepdim=True) + sun
    halfway = halfway / torch.linalg.vector_norm(halfway, dim=-1, keepdim=True)
    cosine = (normals * halfway).sum(-1)
    lobe = torch.exp(SHARP_LOBE * (cosine - 1.0)) + SHEEN_WEIGHT * torch.exp(
        SHEEN_LOBE * (cosine - 1.0))
    wet = torch.exp(points[:, 2].clamp(max=0.0) / WET_FILM_M)
    flat = torch.zeros(viewport.height_px * viewport.width_px, dtype=points.dtype)
    flat = flat.index_put((frags.pixel,), strength * lobe * wet)
    return flat.reshape(viewport.height_px, viewport.width_px)
