"""A fit's meshes as files: the rest-pose mesh and one posed mesh per fitted frame, in PLY,
OBJ or GLB (core/io/mesh_export.py), textured with the fit's own albedo.

The posed meshes are written into a folder that replaces ``posed/`` when all are written
(meshes of the other formats in it are kept), so a kill or a cancel leaves the old set or the
new one complete."""

import threading
from pathlib import Path

import numpy as np

from dolphinfit.core.fit.result import FitResult
from dolphinfit.core.io.atomic import atomic_folder
from dolphinfit.core.io.mesh_export import export_mesh
from dolphinfit.core.model.template import Template
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel

POSED_FOLDER = "posed"


def export_fit_meshes(result: FitResult, template: Template, out_dir: Path, suffix: str = ".ply",
                      progress: ProgressCallback | None = None,
                      cancel: threading.Event | None = None) -> list[Path]:
    """Write ``rest_mesh.SUFFIX`` and ``posed/%06d.SUFFIX`` into ``out_dir``; the paths."""
    albedo = np.round(np.clip(result.albedo, 0.0, 1.0) * 255).astype(np.uint8)
    posed = Path(out_dir) / POSED_FOLDER
    names = [f"{int(frame):06d}{suffix}" for frame in result.frame_idx]
    with atomic_folder(posed, carry=lambda entry: entry.suffix.lower() != suffix) as tmp:
        jobs = [(Path(out_dir) / f"rest_mesh{suffix}", result.rest_verts)]
        jobs += [(tmp / name, verts) for name, verts in zip(names, result.posed_verts)]
        for done, (path, verts) in enumerate(jobs, start=1):
            check_cancel(cancel)
            export_mesh(path, verts, template.faces, template.uvs, template.face_uvs_idx,
                        albedo)
            if progress is not None:
                progress(Progress("meshes", done, len(jobs), path.name))
    return [jobs[0][0], *(posed / name for name in names)]
