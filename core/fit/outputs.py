"""Writing a fit: result.json and result.npz (result_io), the rest mesh, a posed mesh per
fitted frame, PNG overlays.

All of it is written into a folder beside the output folder, which then replaces it: a kill
leaves the old fit or the new one, complete. Other files in the output folder are kept; other
folders are refused, since the folder is replaced as a whole.
"""

from pathlib import Path

import cv2
import numpy as np
import torch

from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.data import FitData
from dolphinfit.core.fit.mesh_files import POSED_FOLDER, export_fit_meshes
from dolphinfit.core.fit.result import FitResult
from dolphinfit.core.fit.result_io import RESULT_JSON, RESULT_NPZ, write_fit_result
from dolphinfit.core.io.atomic import atomic_folder
from dolphinfit.core.io.output_paths import check_output_folder
from dolphinfit.core.measure.receipt import write_png
from dolphinfit.core.io.report import list_some
from dolphinfit.core.model.template import Template
from dolphinfit.core.render.render import Appearance, render
from dolphinfit.core.render.settings import Viewport
from dolphinfit.core.render.shade import SGLight

NUM_OVERLAYS = 4
OVERLAY_FOLDER = "overlays"
MESH_SUFFIX = ".ply"
WRITTEN = frozenset({RESULT_JSON, RESULT_NPZ, f"rest_mesh{MESH_SUFFIX}", POSED_FOLDER,
                     OVERLAY_FOLDER})  # what write_outputs writes into a fit folder
MASK_COLOUR = np.array([255, 200, 0], dtype=np.float32)     # RGB outline of the target mask


def check_fit_folder(out_dir: Path, what: str = "") -> Path:
    """``out_dir`` if a fit can be written there: a new folder, or one whose sub-folders are
    a fit's own; InputError naming it (after ``what``, e.g. "--out ") otherwise."""
    out_dir = check_output_folder(Path(out_dir), what)
    if out_dir.is_dir():
        foreign = sorted(p.name for p in out_dir.iterdir()
                         if p.is_dir() and p.name not in WRITTEN)
        if foreign:
            raise InputError(f"{what}{out_dir}: holds folders that are not a fit's "
                             f"({list_some(foreign)}); give the fit a folder of its own")
    return out_dir


def write_outputs(result: FitResult, data: FitData, template: Template,
                  out_dir: Path) -> list[Path]:
    """Write everything a user needs from a fit into ``out_dir`` (see the module docstring);
    returns the paths."""
    out_dir = check_fit_folder(out_dir)
    with atomic_folder(out_dir, carry=lambda entry: entry.name not in WRITTEN) as tmp:
        written = write_fit_result(result, tmp)
        written += export_fit_meshes(result, template, tmp, MESH_SUFFIX)
        frames = np.linspace(0, data.num_frames - 1, min(NUM_OVERLAYS, data.num_frames))
        for t in frames.astype(int):
            path = tmp / OVERLAY_FOLDER / f"{int(result.frame_idx[t]):06d}.png"
            write_png(path, overlay(result, data, template, int(t)))
            written.append(path)
    return [out_dir / path.relative_to(tmp) for path in written]


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
