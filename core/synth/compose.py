"""Putting the rendered dolphin into the sea: one frame at a time.

The dolphin is rendered only in a region around it, supersampled 2× and averaged down, so its
outline is antialiased and its coverage fraction becomes the alpha of the layer. Water either
follows the fit's model (the paper's transmission filter) or, with ``scattering``, a physical
one: transmission T = exp(−k·depth) plus in-scattered water colour (1 − T). With ``ripples``,
the submerged layer is displaced by the surface slope: a facet tilted by slope s bends the
line of sight by about (1 − 1/n)·s, which moves a point at depth d by d·(1 − 1/n)·s.

A layer can also carry the coverage of named parts (sets of faces, for part masks) and sun
highlights on the wet skin above the water. A second animal is composited first; where it lies
above the target, it hides the target (``occlude``).
"""

from dataclasses import dataclass

import cv2
import numpy as np
import torch
import torch.nn.functional as F

from dolphinfit.core.camera import N_WATER, NadirCamera
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.render.render import Appearance, render
from dolphinfit.core.render.settings import Viewport
from dolphinfit.core.synth.highlight import wet_highlight

SUPERSAMPLE = 2
ROI_MARGIN_PX = 6
VISIBLE_CONTRAST = 0.035   # mean |dolphin − water| colour difference seen as visible
OCCLUSION_MARGIN_M = 0.02  # another animal hides the target only when this much shallower


@dataclass(frozen=True)
class DolphinLayer:
    """The dolphin over a window of the frame: alpha, premultiplied colour, surface depth."""

    x0: int
    y0: int
    alpha: np.ndarray        # (h, w) float32 coverage fraction
    premult: np.ndarray      # (h, w, 3) float32 colour × alpha
    depth_m: np.ndarray      # (h, w) float32 depth below the surface of the covered surface
    parts: np.ndarray | None = None   # (h, w, P) float32 coverage fraction of each part


@dataclass(frozen=True)
class Highlight:
    """Sun highlights on wet skin: the sun's direction (world, unit) and their strength."""

    sun: np.ndarray
    strength: float


def render_layer(verts_world: torch.Tensor, faces: torch.Tensor, appearance: Appearance,
                 intrinsics: CameraIntrinsics, altitude_m: float, refraction: bool,
                 scattering: tuple[np.ndarray, np.ndarray] | None,
                 part_faces: tuple[torch.Tensor, ...] = (),
                 highlight: Highlight | None = None) -> DolphinLayer | None:
    """Supersampled render of one posed mesh (1, V, 3); None when it is out of the frame.

    ``scattering``: (water colour (3,), attenuation (3,) 1/m) for the physical water model,
    or None to keep the appearance's own transmission filter. ``part_faces``: (F,) bool face
    sets whose coverage the layer carries in ``parts``.
    """
    altitude = torch.tensor([altitude_m], dtype=verts_world.dtype)
    camera = NadirCamera(intrinsics, altitude, refraction=refraction)
    xy = camera.project(verts_world)[0]
    x0 = max(int(xy[:, 0].min()) - ROI_MARGIN_PX, 0)
    y0 = max(int(xy[:, 1].min()) - ROI_MARGIN_PX, 0)
    x1 = min(int(xy[:, 0].max()) + ROI_MARGIN_PX + 1, intrinsics.width_px)
    y1 = min(int(xy[:, 1].max()) + ROI_MARGIN_PX + 1, intrinsics.height_px)
    if x1 <= x0 or y1 <= y0:
        return None
    fine = NadirCamera(intrinsics.resized(intrinsics.width_px * SUPERSAMPLE,
                                          intrinsics.height_px * SUPERSAMPLE),
                       altitude, refraction=refraction)
    viewport = Viewport(torch.tensor([x0 * SUPERSAMPLE]), torch.tensor([y0 * SUPERSAMPLE]),
                        (x1 - x0) * SUPERSAMPLE, (y1 - y0) * SUPERSAMPLE)
    with torch.no_grad():
        out = render(verts_world, faces, appearance, fine, viewport)
    coverage = out.coverage[0].to(verts_world.dtype)
    depth = (-out.height_m[0]).clamp(min=0.0)
    rgb = out.rgb[0]
    if highlight is not None and highlight.strength > 0:
        rgb = rgb + wet_highlight(verts_world, faces, fine, viewport,
                                  torch.as_tensor(highlight.sun, dtype=verts_world.dtype),
                                  highlight.strength).to(rgb.dtype)[..., None]
    if scattering is not None:
        water, attenuation = (torch.as_tensor(a, dtype=rgb.dtype) for a in scattering)
        transmit = torch.exp(-depth[..., None] * attenuation)
        rgb = rgb * transmit + water * (1.0 - transmit)

    def pool(image: torch.Tensor) -> np.ndarray:
        return F.avg_pool2d(image.permute(2, 0, 1)[None], SUPERSAMPLE)[0].permute(1, 2, 0).numpy()

    pooled = pool(torch.cat([coverage[..., None], rgb * coverage[..., None],
                             (depth * coverage)[..., None]], -1)).astype(np.float32)
    alpha = pooled[..., 0]
    parts = None
    if part_faces:
        face = out.face_idx[0]
        in_part = [(face >= 0) & members[face.clamp(min=0)] for members in part_faces]
        parts = pool(torch.stack(in_part, -1).to(rgb.dtype)).astype(np.float32)
    return DolphinLayer(x0=x0, y0=y0, alpha=alpha, premult=pooled[..., 1:4],
                        depth_m=pooled[..., 4] / np.maximum(alpha, 1e-6), parts=parts)


def ripple(layer: DolphinLayer, slope: np.ndarray, gsd_m_per_px: float) -> DolphinLayer:
    """The layer displaced by the surface slopes (H, W, 2) of the full frame (module doc)."""
    h, w = layer.alpha.shape
    window = slope[layer.y0:layer.y0 + h, layer.x0:layer.x0 + w]
    shift_px = (1.0 - 1.0 / N_WATER) * layer.depth_m[..., None] * window / gsd_m_per_px
    cols, rows = np.meshgrid(np.arange(w, dtype=np.float32), np.arange(h, dtype=np.float32))
    map_x = cols - shift_px[..., 0]
    map_y = rows + shift_px[..., 1]          # world +y is image −v

    def warp(image: np.ndarray) -> np.ndarray:
        return cv2.remap(image, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)

    parts = None if layer.parts is None else warp(layer.parts).reshape(layer.parts.shape)
    return DolphinLayer(layer.x0, layer.y0, warp(layer.alpha), warp(layer.premult),
                        warp(layer.depth_m), parts)


def occlude(layer: DolphinLayer, front: DolphinLayer | None) -> DolphinLayer:
    """``layer`` less what ``front`` (another animal) hides where it lies above ``layer``."""
    if front is None:
        return layer
    h, w = layer.alpha.shape
    cover = np.zeros((h, w), dtype=np.float32)
    above = np.zeros((h, w), dtype=bool)
    fy0, fx0 = max(front.y0, layer.y0), max(front.x0, layer.x0)
    fy1 = min(front.y0 + front.alpha.shape[0], layer.y0 + h)
    fx1 = min(front.x0 + front.alpha.shape[1], layer.x0 + w)
    if fy1 <= fy0 or fx1 <= fx0:
        return layer
    mine = (slice(fy0 - layer.y0, fy1 - layer.y0), slice(fx0 - layer.x0, fx1 - layer.x0))
    theirs = (slice(fy0 - front.y0, fy1 - front.y0), slice(fx0 - front.x0, fx1 - front.x0))
    cover[mine] = front.alpha[theirs]
    above[mine] = front.depth_m[theirs] < layer.depth_m[mine] - OCCLUSION_MARGIN_M
    keep = np.where(above, 1.0 - cover, 1.0).astype(np.float32)
    parts = None if layer.parts is None else layer.parts * keep[..., None]
    return DolphinLayer(layer.x0, layer.y0, layer.alpha * keep, layer.premult * keep[..., None],
                        layer.depth_m, parts)


def composite(sea_rgb: np.ndarray, layer: DolphinLayer | None,
              body_contrast: float = 1.0) -> tuple[np.ndarray, float]:
    """The frame with the dolphin over the sea, and the dolphin's mean contrast to the water;
    ``body_contrast`` scales the dolphin's difference from the water behind it (1: as
    rendered)."""
    frame = sea_rgb.copy()
    if layer is None or float(layer.alpha.sum()) < 1.0:
        return frame, 0.0
    h, w = layer.alpha.shape
    window = frame[layer.y0:layer.y0 + h, layer.x0:layer.x0 + w]
    alpha = layer.alpha[..., None]
    blended = window * (1.0 - alpha) + layer.premult
    if body_contrast != 1.0:
        blended = window + body_contrast * (blended - window)
    contrast = float((np.abs(blended - window) .sum(-1) * layer.alpha).sum()
                     / (3.0 * layer.alpha.sum()))
    frame[layer.y0:layer.y0 + h, layer.x0:layer.x0 + w] = blended
    return frame, contrast


def layer_coverage(layer: DolphinLayer | None, height_px: int, width_px: int,
                   part: int | None = None) -> np.ndarray:
    """(H, W) float32 share of each pixel the layer covers (``part``: that part's share)."""
    share = np.zeros((height_px, width_px), dtype=np.float32)
    if layer is not None and (part is None or layer.parts is not None):
        h, w = layer.alpha.shape
        share[layer.y0:layer.y0 + h, layer.x0:layer.x0 + w] = (
            layer.alpha if part is None else layer.parts[..., part])
    return share


def finish(frame: np.ndarray, glints: np.ndarray, blur_px: float, noise_sd: float,
           rng: np.random.Generator) -> np.ndarray:
    """Add glints, optical blur and sensor noise; (H, W, 3) uint8 BGR for the video."""
    image = frame + glints[..., None]
    if blur_px > 0:
        image = cv2.GaussianBlur(image, (0, 0), blur_px)
    if noise_sd > 0:
        image = image + rng.normal(0.0, noise_sd, image.shape).astype(np.float32)
    return cv2.cvtColor(np.clip(image * 255.0 + 0.5, 0, 255).astype(np.uint8), cv2.COLOR_RGB2BGR)
