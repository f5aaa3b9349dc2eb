"""Writing a fit: result.json and result.npz (result_io), the rest mesh, a posed mesh per
fitted frame, PNG overlays."""

from pathlib import Path

import cv2
import numpy as np
import torch

from core.fit.data import FitData
from core.fit.result import FitResult
from core.fit.result_io import write_fit_result
from core.fit.mesh_files import export_fit_meshes
from core.model.template import Template
from core.render.render import Appearance, render
from core.render.settings import Viewport
from core.render.shade import SGLight

NUM_OVERLAYS = 4
MASK_COLOUR = np.array([255, 200, 0], dtype=np.float32)     # RGB outline of the target mask


def write_outputs(result: FitResult, data: FitData, template: Template, out_dir: Path) -> list[Path]:
    """Write everything a user needs from a fit into ``out_dir``; returns the paths."""
    out_dir = Path(out_dir)
    written = write_fit_result(result, out_dir)
    written += export_fit_meshes(result, template, out_dir, ".ply")
    for t in np.linspace(0, data.num_frames - 1, min(NUM_OVERLAYS, data.num_frames)).astype(int):
        path = out_dir / "overlays" / f"{int(result.frame_idx[t]):06d}.png"
        path.parent.mkdir(parents=True, exist_ok=True)
        cv2.imwrite(str(path), cv2.cvtColor(overlay(result, data, template, int(t)),
                                            cv2.COLOR_RGB2BGR))
        written.append(path)
    return written


def overlay(result: FitResult, data: FitData, template: Template, t: int) -> np.ndarray:
    """(H, 3·W, 3) uint8 RGB: the frame | the frame with the mask outline | the fitted render."""
    image = data.images[t].numpy()
    mask = (data.masks[t].numpy() > 0.5).astype(np.uint8)
    outline = cv2.morphologyEx(mask, cv2.MORPH_GRADIENT, np.ones((3, 3), np.uint8)) > 0
    with_mask = image * 255.0
    with_mask[outline] = MASK_COLOUR
    appearance = Appearance(
        albedo=torch.as_tensor(result.albedo, dtype=torch.float32),
        face_uvs=torch.tensor(template.uvs[template.face_uvs_idx], dtype=torch.float32),
        light=SGLight(*(torch.as_tensor(result.light[k], dtype=torch.float32)
                        for k in ("axes", "sharpness", "amplitude"))),
        f_water=torch.as_tensor(result.f_water, dtype=torch.float32))
    viewport = Viewport(data.viewport.x0_px[t:t + 1], data.viewport.y0_px[t:t + 1],
                        data.viewport.width_px, data.viewport.height_px)
    with torch.no_grad():
        out = render(torch.as_tensor(result.posed_verts[t:t + 1], dtype=torch.float32),
                     torch.as_tensor(template.faces), appearance, data.camera.select([t]),
                     viewport)
    covered = out.coverage[0].numpy()[..., None]
    rendered = np.where(covered, out.rgb[0].numpy(), image) * 255.0
    panels = [image * 255.0, with_mask, rendered]
    return np.clip(np.concatenate(panels, axis=1), 0, 255).astype(np.uint8)
