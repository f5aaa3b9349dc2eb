"""What a task's outcome depends on, as content hashes: the SHA-256 of every input file (a
folder: of its files' names and hashes) and the options as JSON. Equal digests mean a
finished task need not run again."""

import hashlib
import json
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

from dolphinfit.core.batch.task import BatchTask, FitInputs, MaskMeasurement, ProjectMeasurement
from dolphinfit.core.io.telemetry import find_srt_sidecar
from dolphinfit.core.model.hw_spec import resolve_hw
from dolphinfit.core.project.model import Project
from dolphinfit.core.project.project_file import media_path, project_to_json
from dolphinfit.core.project.results import project_hw_spec


def _file_digest(path: Path) -> str:
    with open(path, "rb") as stream:
        return hashlib.file_digest(stream, "sha256").hexdigest()


def content_digest(path: Path) -> str:
    """SHA-256 of a file, or of a folder's files (relative names and contents, in order)."""
    if not path.is_dir():
        return _file_digest(path)
    digest = hashlib.sha256()
    for file in sorted(p for p in path.rglob("*") if p.is_file()):
        digest.update(f"{file.relative_to(path).as_posix()}\0{_file_digest(file)}\n".encode())
    return digest.hexdigest()


def _fit_inputs(fit: FitInputs) -> tuple[dict[str, Path], dict[str, Any]]:
    files = {"clip": fit.clip}
    altitude_file = find_srt_sidecar(fit.clip) if fit.altitude is None else fit.altitude
    if isinstance(altitude_file, Path):
        files["altitude"] = altitude_file
    if fit.masks is not None:
        files["masks"] = fit.masks
    constant = fit.altitude is not None and not isinstance(fit.altitude, Path)
    config = fit.config.to_json()
    if fit.config.hw_table is not None:  # the table's values, not where it lies
        config["hw_table"] = _hw_table(fit.config.hw_table)
    options = {"altitude_m": float(fit.altitude) if constant else None,
               "launch_height_m": fit.launch_height_m, "time_offset_s": fit.time_offset_s,
               "altitude_calibration": (None if fit.altitude_calibration is None
                                        else fit.altitude_calibration.to_json()),
               "camera": asdict(fit.camera), "config": config,
               "seed": None if fit.masks is not None
               else {"kind": type(fit.seed).__name__, **asdict(fit.seed)}}
    if fit.also_frames:  # a scan's best frames (absent: as before scans existed)
        options["also_frames"] = list(fit.also_frames)
    if fit.lens is not None:  # absent: as before the fit took a lens
        options["lens"] = asdict(fit.lens)
    return files, options


def _animal_project(m: ProjectMeasurement) -> Project:
    """The project cut down to the task's clip and animal, without its saved fit, scan and
    media fingerprint (what the elliptical result depends on; other animals' edits do not
    change it, and the media's content is an input file of its own)."""
    clip = m.project.clips[m.clip_idx]
    animal = replace(clip.animals[m.animal_idx], fit_path=None)
    return replace(m.project, clips=(replace(clip, animals=(animal,), scan_path=None,
                                             rejected_frames=(), media_fingerprint=None),))


def _hw_table(spec: str) -> dict[str, Any]:
    """The HW table's values (a preset or CSV edited in place is a new input)."""
    table = resolve_hw(spec)
    ratios, sd = table.completed()
    return {"name": table.name, "ratios": ratios.tolist(), "sd": sd.tolist()}


def _measurement_inputs(m: MaskMeasurement | ProjectMeasurement
                        ) -> tuple[dict[str, Path], dict[str, Any]]:
    if isinstance(m, MaskMeasurement):
        options = {**asdict(m), "hw_table": _hw_table(m.hw)}
        for name in ("frames", "lens"):  # none given: as before they existed
            if not options[name]:
                del options[name]
        return {}, options
    clip = m.project.clips[m.clip_idx]
    files = {"clip": media_path(m.project_path, clip)}  # its frame times place the altitudes
    if clip.altitude is not None and clip.altitude.path is not None:
        files["altitude"] = m.project_path.parent / clip.altitude.path
    return files, {"project": project_to_json(_animal_project(m)), "num_draws": m.num_draws,
                   "hw_table": _hw_table(project_hw_spec(m.project, m.project_path.parent))}


def task_inputs(task: BatchTask) -> dict[str, Any]:
    """The task's inputs: ``files`` (role → {path, sha256}) and ``options``."""
    files, measurement = _measurement_inputs(task.measurement)
    options = {"measurement": measurement}
    if task.fit is not None:
        fit_files, options["fit"] = _fit_inputs(task.fit)
        files.update(fit_files)
    return {"files": {role: {"path": str(path), "sha256": content_digest(path)}
                      for role, path in files.items()},
            "options": options}


def inputs_digest(inputs: dict[str, Any]) -> str:
    """One SHA-256 of the inputs' hashes and options (paths left out: a moved folder of the
    same files is the same input)."""
    content = {"files": {role: f["sha256"] for role, f in inputs["files"].items()},
               "options": inputs["options"]}
    return hashlib.sha256(json.dumps(content, sort_keys=True).encode()).hexdigest()
