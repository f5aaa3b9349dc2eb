"""The template asset: the rest mesh, skeleton, skinning weights, UVs, albedo and landmarks.

Stored in ``resources/model/`` as a versioned ``.npz`` written deterministically (fixed zip
timestamps, sorted keys) by ``dolphinfit template build``; the runtime model only loads it.

Frames and units: metres, world axes at rest with the rostrum towards +x, dorsal towards +z,
the animal's left towards +y, and the root joint at the origin.
"""

import io
import json
import zipfile
from dataclasses import dataclass, fields
from functools import lru_cache
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.resources import RESOURCES_DIR

FORMAT_VERSION = 1
TEMPLATE_PATH = RESOURCES_DIR / "model" / f"dolphin_template_v{FORMAT_VERSION}.npz"
_ZIP_DATE = (1980, 1, 1, 0, 0, 0)


@dataclass(frozen=True, eq=False)
class Template:
    """The procedural dolphin template (see module docstring for frames and units)."""

    verts: np.ndarray            # (V, 3) float64, rest pose
    faces: np.ndarray            # (F, 3) int64, outward winding
    uvs: np.ndarray              # (U, 2) float64, u → columns, v → rows from the top
    face_uvs_idx: np.ndarray     # (F, 3) int64 into uvs (UV seams split corners, not vertices)
    albedo: np.ndarray           # (512, 512) uint8 grayscale
    skin_weights: np.ndarray     # (V, J) float64, rows sum to one
    rest_joints: np.ndarray      # (J, 3) float64
    joint_parents: np.ndarray    # (J,) int64, −1 for the root; parents precede children
    joint_group: np.ndarray      # (J,) int64 part of each joint (group 0 = root)
    joint_mirror: np.ndarray     # (J,) bool: right-side twin mirroring its group's rotation
    joint_axes: np.ndarray       # (J, 3, 3) float64, columns = part-local x, y, z at rest
    station_fractions: np.ndarray  # (S,) float64, 0.05 … 0.95
    station_rings: np.ndarray    # (S, R) int64 ring vertices, dorsal pair at both ends
    joint_names: tuple[str, ...]
    group_names: tuple[str, ...]
    rostrum_idx: int
    notch_idx: int
    length_m: float
    fin_vertices: dict[str, np.ndarray]  # joint name → vertices grown for that fin
    fin_bases: dict[str, np.ndarray]     # joint name → body vertices its base stands on

    @property
    def group_parents(self) -> np.ndarray:
        """(M,) int64 parent part of each part (−1 for the root), from the joint tree."""
        parents = np.full(len(self.group_names), -1, dtype=np.int64)
        for joint, parent in enumerate(self.joint_parents):
            group = self.joint_group[joint]
            if parent >= 0 and parents[group] < 0 and self.joint_group[parent] != group:
                parents[group] = self.joint_group[parent]
        return parents


_SCALARS = ("joint_names", "group_names", "rostrum_idx", "notch_idx", "length_m")
_DICTS = ("fin_vertices", "fin_bases")


def save_template(template: Template, path: Path) -> None:
    """Write ``template`` to ``path`` atomically and byte-for-byte deterministically."""
    arrays: dict[str, np.ndarray] = {}
    meta: dict[str, object] = {"format_version": FORMAT_VERSION}
    for field in fields(Template):
        value = getattr(template, field.name)
        if field.name in _SCALARS:
            meta[field.name] = list(value) if isinstance(value, tuple) else value
        elif field.name in _DICTS:
            meta[field.name] = sorted(value)
            arrays.update({f"{field.name}.{key}": array for key, array in value.items()})
        else:
            arrays[field.name] = value
    arrays["meta"] = np.frombuffer(json.dumps(meta, sort_keys=True).encode(), dtype=np.uint8)

    with atomic_path(Path(path)) as tmp, zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as zf:
        for key in sorted(arrays):
            buffer = io.BytesIO()
            np.lib.format.write_array(buffer, np.ascontiguousarray(arrays[key]),
                                      allow_pickle=False)
            info = zipfile.ZipInfo(f"{key}.npy", date_time=_ZIP_DATE)
            info.compress_type = zipfile.ZIP_DEFLATED
            zf.writestr(info, buffer.getvalue())


def load_template(path: Path | None = None) -> Template:
    """Read a template asset (default: the bundled one); InputError if unreadable."""
    if path is None:
        return _bundled_template()
    return _read_template(Path(path))


@lru_cache(maxsize=1)
def _bundled_template() -> Template:
    return _read_template(TEMPLATE_PATH)


def _read_template(path: Path) -> Template:
    if not path.exists():
        raise InputError(f"{path}: template asset not found (run `dolphinfit template build`)")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {key: data[key] for key in data.files}
        meta = json.loads(arrays.pop("meta").tobytes().decode())
    except (OSError, ValueError, KeyError, zipfile.BadZipFile) as exc:
        raise InputError(f"{path}: not a readable template asset ({exc})") from exc
    if meta.get("format_version") != FORMAT_VERSION:
        raise InputError(f"{path}: template format {meta.get('format_version')!r}, "
                         f"this version of dolphinfit reads {FORMAT_VERSION}")
    kwargs: dict[str, object] = {}
    for field in fields(Template):
        if field.name in _SCALARS:
            value = meta[field.name]
            kwargs[field.name] = tuple(value) if isinstance(value, list) else value
        elif field.name in _DICTS:
            kwargs[field.name] = {key: arrays[f"{field.name}.{key}"] for key in meta[field.name]}
        else:
            kwargs[field.name] = arrays[field.name]
    return Template(**kwargs)
