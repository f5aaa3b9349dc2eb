"""A fit on disk and back: result.json (figures, per-frame pose, history, configuration,
status) and result.npz beside it (every array exactly as fitted), both written atomically.

``read_fit_result`` restores the FitResult that was written, field for field.
"""

import zipfile
import zlib
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.result import RESULT_SCHEMA_VERSION, STATUSES, FitResult
from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.io.json_file import check_schema_version, read_json, write_json

RESULT_JSON = "result.json"
RESULT_NPZ = "result.npz"
ARRAYS = ("betas", "pose_aa", "transl", "frame_idx", "time_s", "iou", "rest_verts",
          "posed_verts", "faces", "albedo", "f_water")
PER_FRAME = ("pose_aa", "transl", "time_s", "iou", "posed_verts")   # leading axis T
LIGHT_PREFIX = "light_"
PROFILE = "profile"   # only in fits with a profile field
# What a fit made before a configuration field existed did, where the field's default now
# says otherwise: such a result reads back with these, not with today's defaults.
# Nested objects (the loss weights) likewise, field by field.
FIELDS_BEFORE = {"colour_geometry": "all_stages", "profile_field": False, "hw_table": None,
                 "weights": {"depth": 0.0}}
SCALARS = ("volume_m3", "length_m", "bci", "mass_kg", "density_kg_m3")


def write_fit_result(result: FitResult, out_dir: Path) -> list[Path]:
    """Write result.npz and result.json into ``out_dir``; returns their paths."""
    npz, json_path = Path(out_dir) / RESULT_NPZ, Path(out_dir) / RESULT_JSON
    arrays = {name: getattr(result, name) for name in ARRAYS}
    if result.profile is not None:
        arrays[PROFILE] = result.profile
    arrays.update({LIGHT_PREFIX + key: value for key, value in result.light.items()})
    with atomic_path(npz) as tmp:
        np.savez_compressed(tmp, **arrays)
    write_json(json_path, result.to_json())
    return [json_path, npz]


def read_fit_result(out_dir: Path) -> FitResult:
    """The FitResult written into ``out_dir``; InputError naming the file that is missing,
    unreadable, of another schema version or inconsistent."""
    json_path, npz = Path(out_dir) / RESULT_JSON, Path(out_dir) / RESULT_NPZ
    data = read_json(json_path, "the fit result")
    check_schema_version(data, RESULT_SCHEMA_VERSION, str(json_path))
    arrays = _read_arrays(npz)
    try:
        status = data["status"]
        if status not in STATUSES:
            raise ValueError(f"unknown status {status!r}")
        fields = dict(
            **{name: float(data[name]) for name in SCALARS},
            loss_history=tuple(data["loss_history"]), timings_s=dict(data["timings"]),
            config=FitConfig.from_json(_as_made(data["config"], FIELDS_BEFORE)),
            warnings=tuple(data["warnings"]),
            status=status, status_message=str(data["status_message"]),
            reasons=tuple(str(reason) for reason in data.get("reasons", ())),
            edge_blur_px=float(data.get("edge_blur_px") or "nan"))   # null or absent: none
        num_frames = len(data["frames"])
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{json_path}: not a complete fit result ({exc!r})") from None
    light = {name[len(LIGHT_PREFIX):]: value for name, value in arrays.items()
             if name.startswith(LIGHT_PREFIX)}
    result = FitResult(**{name: arrays[name] for name in ARRAYS}, light=light,
                       profile=arrays.get(PROFILE), **fields)
    lengths = {len(result.frame_idx), num_frames, *(len(getattr(result, n)) for n in PER_FRAME)}
    if len(lengths) != 1:
        raise InputError(f"{npz}: its per-frame arrays do not match the {num_frames} frames "
                         f"of {json_path}")
    return result


def _as_made(saved: dict, before: dict) -> dict:
    """A saved configuration object with ``before``'s value for each field it predates,
    within nested objects too."""
    if not isinstance(saved, dict):
        raise TypeError(f"a configuration object is a {type(saved).__name__}")
    made = dict(saved)
    for name, value in before.items():
        if name not in saved:
            made[name] = value
        elif isinstance(value, dict) and isinstance(saved[name], dict):
            made[name] = _as_made(saved[name], value)
    return made


def _read_arrays(path: Path) -> dict[str, np.ndarray]:
    """Every array of the npz, read in full (so truncation shows here)."""
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {name: npz[name] for name in npz.files}
    except FileNotFoundError:
        raise InputError(f"{path}: the fit's arrays are missing") from None
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
        raise InputError(f"{path}: not a readable .npz file ({exc})") from None
    missing = [name for name in ARRAYS if name not in arrays]
    if missing or not any(name.startswith(LIGHT_PREFIX) for name in arrays):
        raise InputError(f"{path}: arrays missing: {', '.join(missing) or 'the light'}")
    return arrays
