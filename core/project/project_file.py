"""Project files: the project tree as JSON, media paths relative to the file, atomic writes.

Schema version 1 (``*.dolphinfit``)::

    {
      "schema_version": 1,
      "settings": {"hw_ratios": "tursiops-provisional", "tail": "extrapolated"},
      "clips": [{
        "media": "DJI_0042.MP4", "kind": "video", "masks": "DJI_0042_masks",
        "media_fingerprint": "v1:9f86d0…",
        "scan": "survey.scans/DJI_0042_scan.json", "rejected_frames": [[1, 150]],
        "lens": {"width_px": 5120, "height_px": 2700, "fx_px": …, "distortion": [k1, k2, p1,
                 p2, k3], …},
        "camera": {"preset": "dji-mavic3-5.1k", "description": "DJI Mavic 3, …",
                   "focal_mm": 12.29, "sensor_width_mm": 17.27, "image_width_px": 5120,
                   "image_height_px": 2700, "approximate": false},
        "altitude": {"path": "DJI_0042.SRT", "constant_m": null, "launch_height_m": 1.5,
                     "time_offset_s": 0.0, "source": "barometer"},
        "altitude_calibration": "Mavic 3 barometer",
        "animals": [{"id": "dolphin 1", "notes": "", "fit": {"settings": {"start_s": null,
          "end_s": null, "fps": 5.0, "quality": "standard", "refraction": false, "roi": true},
          "result": "survey.fits/DJI_0042_dolphin-1"}, "measurements": [{
          "frame_idx": 120, "midline_px": [[u, v], ...], "mirror_side": null, "notes": "",
          "stations": [{"station_pct": 5, "side_a_px": 12.5, "side_b_px": -12.1,
                        "side_b_source": "suggested", "skipped": false}, ...]}]}]
      }],
      "calibrations": [{"name": "Mavic 3 barometer", "object_length_m": 2.0,
        "camera": {...}, "altimeter": "barometer", "shots": [{"image": "board_12m.jpg",
        "recorded_altitude_m": 12.1, "pixel_length": 812.4, "ends_px": [[u, v], [u, v]]}]}]
    }

Pixels (midline clicks; each edge as its signed distance from the midline along the station's
normal, side A positive) are kept apart from the calibration (camera, altitude), so a corrected
altitude rescales everything without re-annotation. The camera's values are stored with the
preset's name, so a project opens unchanged where that preset is unknown; a clip's camera is
null while unknown (core.project.model.ClipEntry), and "description" may be absent. An edge's
``side_a_source`` / ``side_b_source`` (core.measure.edge_sources) is written only where it is
not ``clicked``, so a missing one (every file from before) reads as clicked.

The autosave file is the project file's sibling ``NAME.autosave``; it is written after edits
and removed on save, so one that is newer than its project marks unsaved work (a crash).
"""

import math
import os
from dataclasses import asdict, replace
from pathlib import Path
from typing import Any

import numpy as np

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.json_file import (
    check_schema_version, dataclass_from_json, json_field, read_json, write_json,
)
from dolphinfit.core.measure.edge_sources import EDGE_CLICKED, NO_EDGE, SOURCE_JSON_KEYS
from dolphinfit.core.measure.lens import LensModel, checked_lens
from dolphinfit.core.measure.stations import NUM_STATIONS, STATION_PCT
from dolphinfit.core.project.fit_settings import FitSettings
from dolphinfit.core.project.model import (
    AltitudeCalibrationSet, AltitudeSpec, Animal, ClipEntry, Measurement, ObjectShot, Project,
)

SCHEMA_VERSION = 1
PROJECT_SUFFIX = ".dolphinfit"
AUTOSAVE_SUFFIX = ".autosave"
RELINK_MAX_MATCHES = 20  # stop searching a project's folder after this many same-name files


def _get(data: Any, key: str, types: type | tuple[type, ...], where: str,
         optional: bool = False) -> Any:
    """``data[key]`` checked against ``types`` (a JSON true is no number); InputError naming
    ``where`` and the key otherwise. ``optional``: a missing key or null gives None."""
    if not isinstance(data, dict):
        raise InputError(f"{where}: expected an object")
    if optional and data.get(key) is None:
        return None
    value = json_field(data, key, types, where)
    if isinstance(value, float) and not math.isfinite(value):
        raise InputError(f"{where}: {key!r} is not a finite number")
    return value


NUMBER = (int, float)


def _camera_from_json(data: Any, where: str) -> tuple[CameraPreset, str | None]:
    preset = _get(data, "preset", str, where, optional=True)
    values = {key: _get(data, key, int if key.endswith("_px") else NUMBER, where)
              for key in ("focal_mm", "sensor_width_mm", "image_width_px", "image_height_px")}
    approximate = _get(data, "approximate", bool, where, optional=True) or False
    description = (_get(data, "description", str, where, optional=True) or preset
                   or "camera values of the project")
    try:
        camera = CameraPreset(name=preset or "explicit", description=description,
                              source=where, approximate=approximate, **values)
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc
    return camera, preset


def _camera_to_json(camera: CameraPreset | None,
                    preset_name: str | None) -> dict[str, Any] | None:
    if camera is None:
        return None
    return {"preset": preset_name, "description": camera.description,
            "focal_mm": camera.focal_mm, "sensor_width_mm": camera.sensor_width_mm,
            "image_width_px": camera.image_width_px, "image_height_px": camera.image_height_px,
            "approximate": camera.approximate}


def _altitude_from_json(data: Any, where: str) -> AltitudeSpec | None:
    if data is None:
        return None
    try:
        return AltitudeSpec(
            path=_get(data, "path", str, where, optional=True),
            constant_m=_get(data, "constant_m", NUMBER, where, optional=True),
            launch_height_m=float(_get(data, "launch_height_m", NUMBER, where)),
            time_offset_s=float(_get(data, "time_offset_s", NUMBER, where)),
            source=_get(data, "source", str, where))
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc


def _altitude_to_json(spec: AltitudeSpec | None) -> dict[str, Any] | None:
    if spec is None:
        return None
    return {"path": spec.path, "constant_m": spec.constant_m,
            "launch_height_m": spec.launch_height_m, "time_offset_s": spec.time_offset_s,
            "source": spec.source}


def _point_list(data: Any, where: str) -> np.ndarray:
    if not isinstance(data, list):
        raise InputError(f"{where}: expected a list of [u, v] points")
    for i, p in enumerate(data):
        if (not isinstance(p, list) or len(p) != 2 or any(
                isinstance(x, bool) or not isinstance(x, NUMBER) or not math.isfinite(x)
                for x in p)):
            raise InputError(f"{where}[{i}]: expected [u, v] in pixels, got {p!r}")
    return np.asarray(data, dtype=np.float64).reshape(-1, 2)


def _measurement_from_json(data: Any, where: str) -> Measurement:
    stations = _get(data, "stations", list, where)
    if len(stations) != NUM_STATIONS:
        raise InputError(f"{where}: expected the {NUM_STATIONS} stations, got {len(stations)}")
    offsets = np.full((NUM_STATIONS, 2), np.nan)
    sources = []  # absent: NO_EDGE, which a placed edge reads as clicked
    skipped = np.zeros(NUM_STATIONS, bool)
    for idx, (entry, pct) in enumerate(zip(stations, STATION_PCT)):
        at = f"{where}: stations[{idx}]"
        if _get(entry, "station_pct", NUMBER, at) != pct:
            raise InputError(f"{at}: station_pct {entry['station_pct']!r}, expected {pct:g}")
        for side, key in enumerate(("side_a_px", "side_b_px")):
            value = _get(entry, key, NUMBER, at, optional=True)
            offsets[idx, side] = np.nan if value is None else value
        sources.append([_get(entry, key, str, at, optional=True) or NO_EDGE
                        for key in SOURCE_JSON_KEYS])
        skipped[idx] = bool(_get(entry, "skipped", bool, at, optional=True))
    frame_idx = _get(data, "frame_idx", int, where)
    try:
        return Measurement(
            frame_idx=frame_idx, midline_px=_point_list(_get(data, "midline_px", list, where),
                                                        f"{where}: midline_px"),
            offsets_px=offsets, skipped=skipped,
            mirror_side=_get(data, "mirror_side", str, where, optional=True),
            notes=_get(data, "notes", str, where, optional=True) or "", edge_sources=sources)
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc


def _measurement_to_json(m: Measurement) -> dict[str, Any]:
    stations = [{"station_pct": pct,
                 "side_a_px": None if np.isnan(a) else float(a),
                 "side_b_px": None if np.isnan(b) else float(b),
                 **{key: source for key, source in zip(SOURCE_JSON_KEYS, sources)
                    if source not in (NO_EDGE, EDGE_CLICKED)},
                 "skipped": bool(skip)}
                for pct, (a, b), sources, skip in zip(STATION_PCT, m.offsets_px,
                                                      m.edge_sources.tolist(), m.skipped)]
    return {"frame_idx": m.frame_idx, "midline_px": m.midline_px.tolist(),
            "mirror_side": m.mirror_side, "notes": m.notes, "stations": stations}


def _fit_settings_from_json(data: Any, where: str) -> FitSettings:
    if data is None:
        return FitSettings()
    try:
        return FitSettings(
            start_s=_get(data, "start_s", NUMBER, where, optional=True),
            end_s=_get(data, "end_s", NUMBER, where, optional=True),
            fps=float(_get(data, "fps", NUMBER, where)),
            quality=_get(data, "quality", str, where),
            refraction=_get(data, "refraction", bool, where),
            roi=_get(data, "roi", bool, where))
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc


def _animal_from_json(data: Any, where: str) -> Animal:
    measurements = [_measurement_from_json(m, f"{where}: measurements[{i}]")
                    for i, m in enumerate(_get(data, "measurements", list, where))]
    frames = [m.frame_idx for m in measurements]
    if len(set(frames)) != len(frames):
        raise InputError(f"{where}: the same frame is measured twice")
    fit = data.get("fit") or {}
    return Animal(animal_id=_get(data, "id", str, where),
                  notes=_get(data, "notes", str, where, optional=True) or "",
                  measurements=tuple(sorted(measurements, key=lambda m: m.frame_idx)),
                  fit_settings=_fit_settings_from_json(fit.get("settings"),
                                                       f"{where}: fit.settings"),
                  fit_path=_get(fit, "result", str, f"{where}: fit", optional=True),
                  fit_inputs=_fit_inputs_from_json(fit.get("inputs"), f"{where}: fit.inputs"))


def _fit_inputs_from_json(data: Any, where: str) -> tuple[tuple[str, str], ...]:
    """What a fit was made from (core.project.fit_inputs): a name-to-digest object, or none."""
    if data is None:
        return ()
    if not isinstance(data, dict) or not all(isinstance(k, str) and isinstance(v, str)
                                             for k, v in data.items()):
        raise InputError(f"{where}: expected an object of names and digests, got {data!r}")
    return tuple(data.items())


def _clip_from_json(data: Any, where: str) -> ClipEntry:
    camera, preset = None, None   # null: the camera is unknown
    if _get(data, "camera", (dict, type(None)), where) is not None:
        camera, preset = _camera_from_json(data["camera"], f"{where}: camera")
    animals = tuple(_animal_from_json(a, f"{where}: animals[{i}]")
                    for i, a in enumerate(_get(data, "animals", list, where)))
    try:
        return ClipEntry(media_path=_get(data, "media", str, where),
                         kind=_get(data, "kind", str, where), camera=camera, preset_name=preset,
                         altitude=_altitude_from_json(data.get("altitude"),
                                                      f"{where}: altitude"),
                         animals=animals,
                         masks_path=_get(data, "masks", str, where, optional=True),
                         altitude_calibration=_get(data, "altitude_calibration", str, where,
                                                   optional=True),
                         scan_path=_get(data, "scan", str, where, optional=True),
                         rejected_frames=_rejected_frames(data.get("rejected_frames"),
                                                          f"{where}: rejected_frames"),
                         lens=_lens_from_json(data.get("lens"), f"{where}: lens"),
                         media_fingerprint=_get(data, "media_fingerprint", str, where,
                                                optional=True))
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc


def _lens_from_json(data: Any, where: str) -> LensModel | None:
    return None if data is None else checked_lens(dataclass_from_json(LensModel, data, where),
                                                  where)


def _optional_to_json(clip: ClipEntry) -> dict[str, Any]:
    """The clip's scan, frames put aside, lens model and media fingerprint, where it has
    them (a clip without them is written as before they existed)."""
    written: dict[str, Any] = {}
    if clip.media_fingerprint is not None:
        written["media_fingerprint"] = clip.media_fingerprint
    if clip.lens is not None:
        written["lens"] = asdict(clip.lens)
    if clip.scan_path is not None:
        written["scan"] = clip.scan_path
    if clip.rejected_frames:
        written["rejected_frames"] = [list(pair) for pair in clip.rejected_frames]
    return written


def _rejected_frames(data: Any, where: str) -> tuple[tuple[int, int], ...]:
    """[[scan animal number, frame], ...] (absent: none)."""
    if data is None:
        return ()
    pairs = data if isinstance(data, list) else None
    if pairs is None or not all(isinstance(p, list) and len(p) == 2 and all(
            isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in p)
            for p in pairs):
        raise InputError(f"{where}: expected a list of [animal, frame] pairs of whole numbers "
                         "≥ 0")
    return tuple((animal, frame) for animal, frame in pairs)


def _shot_from_json(data: Any, where: str) -> ObjectShot:
    ends = data.get("ends_px") if isinstance(data, dict) else None
    if ends is not None:
        ends = _point_list(ends, f"{where}: ends_px")
        if len(ends) != 2:
            raise InputError(f"{where}: ends_px must be the object's two ends, got "
                             f"{len(ends)} points")
    try:
        return ObjectShot(
            image=_get(data, "image", str, where),
            recorded_altitude_m=_get(data, "recorded_altitude_m", NUMBER, where),
            pixel_length=_get(data, "pixel_length", NUMBER, where),
            ends_px=None if ends is None else tuple((float(u), float(v)) for u, v in ends))
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc


def _calibration_from_json(data: Any, where: str) -> AltitudeCalibrationSet:
    camera, _ = _camera_from_json(_get(data, "camera", dict, where), f"{where}: camera")
    shots = tuple(_shot_from_json(shot, f"{where}: shots[{i}]")
                  for i, shot in enumerate(_get(data, "shots", list, where)))
    try:
        return AltitudeCalibrationSet(
            name=_get(data, "name", str, where),
            object_length_m=_get(data, "object_length_m", NUMBER, where), camera=camera,
            altimeter=_get(data, "altimeter", str, where), shots=shots)
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc


def _calibration_to_json(calibration: AltitudeCalibrationSet) -> dict[str, Any]:
    return {"name": calibration.name, "object_length_m": calibration.object_length_m,
            "camera": _camera_to_json(calibration.camera, None),
            "altimeter": calibration.altimeter,
            "shots": [{"image": shot.image, "recorded_altitude_m": shot.recorded_altitude_m,
                       "pixel_length": shot.pixel_length,
                       "ends_px": None if shot.ends_px is None else [list(p) for p in shot.ends_px]}
                      for shot in calibration.shots]}


def project_from_json(data: Any, where: str) -> Project:
    """Parse a project file's JSON object; ``where`` names the file in errors."""
    check_schema_version(data, SCHEMA_VERSION, where)
    settings = _get(data, "settings", dict, where)
    clips = tuple(_clip_from_json(c, f"{where}: clips[{i}]")
                  for i, c in enumerate(_get(data, "clips", list, where)))
    calibrations = tuple(_calibration_from_json(c, f"{where}: calibrations[{i}]")
                         for i, c in enumerate(_get(data, "calibrations", list, where,
                                                    optional=True) or ()))
    try:
        return Project(clips=clips,
                       hw_ratios=_get(settings, "hw_ratios", str, f"{where}: settings"),
                       tail=_get(settings, "tail", str, f"{where}: settings"),
                       calibrations=calibrations)
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc


def project_to_json(project: Project) -> dict[str, Any]:
    """The JSON object of a project file (inverse of ``project_from_json``)."""
    return {
        "schema_version": SCHEMA_VERSION,
        "settings": {"hw_ratios": project.hw_ratios, "tail": project.tail},
        "clips": [{
            "media": clip.media_path, "kind": clip.kind, "masks": clip.masks_path,
            "camera": _camera_to_json(clip.camera, clip.preset_name),
            "altitude": _altitude_to_json(clip.altitude),
            "altitude_calibration": clip.altitude_calibration,
            **_optional_to_json(clip),
            "animals": [{"id": a.animal_id, "notes": a.notes,
                         "measurements": [_measurement_to_json(m) for m in a.measurements],
                         "fit": {"settings": asdict(a.fit_settings), "result": a.fit_path,
                                 **({"inputs": dict(a.fit_inputs)} if a.fit_inputs else {})}}
                        for a in clip.animals],
        } for clip in project.clips],
        "calibrations": [_calibration_to_json(c) for c in project.calibrations],
    }


def read_project(path: Path) -> Project:
    """Read a project (or autosave) file; InputError naming the file and the faulty entry."""
    return project_from_json(read_json(path, "the project"), str(path))


def write_project(path: Path, project: Project) -> None:
    """Write a project file atomically (temporary file, then rename)."""
    write_json(path, project_to_json(project))


def autosave_path(project_path: Path) -> Path:
    """The autosave sibling of a project file: ``NAME.autosave``."""
    return project_path.with_name(project_path.name + AUTOSAVE_SUFFIX)


def has_newer_autosave(project_path: Path) -> bool:
    """Whether unsaved work from an earlier session waits beside ``project_path``."""
    autosave = autosave_path(project_path)
    if not autosave.exists():
        return False
    return not project_path.exists() or autosave.stat().st_mtime >= project_path.stat().st_mtime


def relative_media_path(project_dir: Path, media: Path) -> str:
    """``media`` relative to the project's folder, with POSIX separators."""
    return Path(os.path.relpath(Path(media).resolve(), Path(project_dir).resolve())).as_posix()


def media_path(project_path: Path, clip: ClipEntry) -> Path:
    """Absolute path of a clip's media."""
    return (project_path.parent / clip.media_path).resolve()


def rebase_media(project: Project, old_dir: Path, new_dir: Path) -> Project:
    """The project with its media, altitude, masks, scan, fit and HW-table paths made relative
    to ``new_dir`` (Save As)."""
    def moved(rel: str) -> str:
        return relative_media_path(new_dir, (old_dir / rel).resolve())

    clips = tuple(replace(
        clip, media_path=moved(clip.media_path),
        altitude=(clip.altitude if clip.altitude is None or clip.altitude.path is None
                  else replace(clip.altitude, path=moved(clip.altitude.path))),
        masks_path=None if clip.masks_path is None else moved(clip.masks_path),
        scan_path=None if clip.scan_path is None else moved(clip.scan_path),
        animals=tuple(a if a.fit_path is None else replace(a, fit_path=moved(a.fit_path))
                      for a in clip.animals))
        for clip in project.clips)
    hw = project.hw_ratios
    if hw.lower().endswith(".csv") and not Path(hw).is_absolute():
        hw = moved(hw)  # a table of the project's own (e.g. from a fit)
    return replace(project, clips=clips, hw_ratios=hw)


def missing_media(project_path: Path, project: Project) -> list[int]:
    """Indices of the clips whose media is not where the project says."""
    return [i for i, clip in enumerate(project.clips)
            if not media_path(project_path, clip).exists()]


def find_moved_media(search_dir: Path, name: str) -> list[Path]:
    """Files or folders called ``name`` under ``search_dir`` (the relink candidates)."""
    found: list[Path] = []
    for root, dirs, files in os.walk(search_dir):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        found += [Path(root) / n for n in sorted([*files, *dirs]) if n == name]
        if len(found) >= RELINK_MAX_MATCHES:
            break
    return found


def relink_clip(project: Project, project_path: Path, clip_idx: int, new_media: Path) -> Project:
    """The project with clip ``clip_idx`` pointing at ``new_media``; an altitude file or masks
    that sat beside the old media and are missing now are looked for beside the new one."""
    clip = project.clips[clip_idx]
    project_dir = project_path.parent

    def moved_too(rel: str | None) -> str | None:
        if rel is None or (project_dir / rel).exists():
            return rel
        candidate = Path(new_media).parent / Path(rel).name
        return relative_media_path(project_dir, candidate) if candidate.exists() else rel

    altitude = clip.altitude
    if altitude is not None and altitude.path is not None:
        altitude = replace(altitude, path=moved_too(altitude.path))
    clips = list(project.clips)
    clips[clip_idx] = replace(clip, media_path=relative_media_path(project_dir, new_media),
                              altitude=altitude, masks_path=moved_too(clip.masks_path))
    return replace(project, clips=tuple(clips))
