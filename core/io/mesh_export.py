"""Writing meshes for any mesh viewer: PLY (vertex colours), OBJ (+ MTL and PNG) and GLB.

PLY keeps the closed, watertight vertex set and bakes the albedo into vertex colours. OBJ and
GLB carry the UV map and the albedo texture; since a vertex has one UV there, vertices on UV
seams are split (the surface stays closed, but viewers see seams as separate vertices). Every
file (an OBJ's material and texture too) is written atomically.
"""

from pathlib import Path

import numpy as np
import trimesh
from PIL import Image

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.atomic import atomic_path

MESH_SUFFIXES = (".ply", ".obj", ".glb")


def export_mesh(path: Path, verts: np.ndarray, faces: np.ndarray, uvs: np.ndarray,
                face_uvs_idx: np.ndarray, albedo: np.ndarray) -> None:
    """Write a textured mesh; the format follows the suffix of ``path``.

    verts: (V, 3) float metres; faces: (F, 3) int; uvs: (U, 2) with v measured from the top
    row of ``albedo`` (H, W) uint8; face_uvs_idx: (F, 3) int into uvs.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES:
        raise InputError(f"{path}: unsupported mesh format {suffix!r} "
                         f"(use one of {', '.join(MESH_SUFFIXES)})")
    if suffix == ".ply":
        mesh = trimesh.Trimesh(verts, faces, process=False,
                               vertex_colors=_vertex_colours(faces, uvs, face_uvs_idx, albedo))
    else:
        mesh = _textured_mesh(verts, faces, uvs, face_uvs_idx, albedo)
    files = {path: None}
    if suffix == ".obj":  # the material and texture files the OBJ names, beside it
        text, textures = trimesh.exchange.obj.export_obj(mesh, return_texture=True)
        files = {path: text.encode("utf-8"),
                 **{path.with_name(name): data for name, data in textures.items()}}
    for target, data in files.items():
        with atomic_path(target) as tmp:
            if data is None:
                mesh.export(tmp, file_type=suffix.lstrip("."))
            else:
                tmp.write_bytes(data)


def _sample(albedo: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Nearest texel of ``albedo`` at each UV (v from the top row)."""
    height, width = albedo.shape[:2]
    cols = np.clip((uv[:, 0] * width).astype(int), 0, width - 1)
    rows = np.clip((uv[:, 1] * height).astype(int), 0, height - 1)
    return albedo[rows, cols]


def _vertex_colours(faces: np.ndarray, uvs: np.ndarray, face_uvs_idx: np.ndarray,
                    albedo: np.ndarray) -> np.ndarray:
    """(V, 4) uint8 RGBA: the albedo at one UV of each vertex."""
    uv_of_vertex = np.zeros((faces.max() + 1, 2))
    uv_of_vertex[faces.ravel()] = uvs[face_uvs_idx.ravel()]
    grey = _sample(albedo, uv_of_vertex)
    return np.column_stack([grey, grey, grey, np.full_like(grey, 255)]).astype(np.uint8)


def _textured_mesh(verts: np.ndarray, faces: np.ndarray, uvs: np.ndarray,
                   face_uvs_idx: np.ndarray, albedo: np.ndarray) -> trimesh.Trimesh:
    """Mesh with one vertex per distinct (vertex, UV) corner and the albedo as texture."""
    corners = np.stack([faces.ravel(), face_uvs_idx.ravel()], axis=1)
    unique, inverse = np.unique(corners, axis=0, return_inverse=True)
    uv = uvs[unique[:, 1]].copy()
    uv[:, 1] = 1.0 - uv[:, 1]  # OBJ/glTF loaders in trimesh count v from the bottom row
    image = Image.fromarray(albedo).convert("RGB")
    visual = trimesh.visual.TextureVisuals(
        uv=uv, material=trimesh.visual.material.SimpleMaterial(image=image))
    return trimesh.Trimesh(verts[unique[:, 0]], inverse.reshape(-1, 3), visual=visual,
                           process=False)
