"""Annotation files: one annotated frame as JSON, pixels and calibration kept apart.

Schema version 1::

    {
      "schema_version": 1,
      "image": {"image_id": "DJI_0042 f1234", "media_path": "DJI_0042.MP4", "frame_idx": 1234},
      "camera": {"preset": "dji-mavic3-5.1k"},
      "altitude": {"altitude_m": 20.3, "source": "laser"},
      "midline_px": [[u, v], ...],
      "mirror_side": null,
      "stations": [
        {"station_pct": 5, "side_a_px": [u, v], "side_b_px": [u, v]},
        {"station_pct": 10, "skipped": true},
        ...
      ],
      "notes": ""
    }

``camera`` is either a preset name (resolved through core.camera_presets, so correcting a preset
corrects every annotation using it) or explicit ``focal_mm``, ``sensor_width_mm``,
``image_width_px`` and ``image_height_px``. ``altitude.source`` is laser, barometer or manual.
``midline_px`` runs from the rostrum tip to the fluke notch. ``stations`` lists the 19 stations
in order; in mirror mode (``mirror_side`` "A" or "B") only that side is needed. ``media_path``
is relative to the JSON file's folder. Writes are atomic.
"""

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from dolphinfit.core.camera_presets import CameraPreset, get_preset
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.json_file import check_schema_version, json_field, read_json, write_json
from dolphinfit.core.measure.annotation import (
    ALTITUDE_SOURCES, SIDES, Annotation, Calibration,
)
from dolphinfit.core.limits import ALTITUDE_M, FOCAL_MM, IMAGE_SIZE_PX, SENSOR_WIDTH_MM, in_range
from dolphinfit.core.measure.stations import NUM_STATIONS, STATION_PCT

SCHEMA_VERSION = 1
SIDE_KEYS = ("side_a_px", "side_b_px")
EXPLICIT_CAMERA_KEYS = ("focal_mm", "sensor_width_mm", "image_width_px", "image_height_px")
CAMERA_LIMITS = {"focal_mm": FOCAL_MM, "sensor_width_mm": SENSOR_WIDTH_MM,
                 "image_width_px": IMAGE_SIZE_PX, "image_height_px": IMAGE_SIZE_PX}
TOP_KEYS = {"schema_version", "image", "camera", "altitude", "midline_px", "mirror_side",
            "stations", "notes"}


@dataclass(frozen=True)
class AnnotationFile:
    """An annotation with its calibration and image metadata, as stored in one JSON file."""

    annotation: Annotation
    calibration: Calibration
    image_id: str = ""
    media_path: str = ""
    notes: str = ""


def _point(value: Any, where: str) -> np.ndarray:
    """A [u, v] pair of finite numbers as a (2,) array."""
    if (not isinstance(value, list) or len(value) != 2
            or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                       and math.isfinite(x) for x in value)):
        raise InputError(f"{where}: expected [u, v] in pixels, got {value!r}")
    return np.asarray(value, dtype=np.float64)


def _camera(data: Any, where: str) -> tuple[CameraPreset, str | None]:
    """The camera section: a preset reference or explicit values."""
    if isinstance(data, dict) and set(data) == {"preset"}:
        name = json_field(data, "preset", str, where)
        return get_preset(name), name
    if not isinstance(data, dict) or set(data) != set(EXPLICIT_CAMERA_KEYS):
        raise InputError(f"{where}: expected {{'preset': NAME}} or the keys "
                         f"{', '.join(EXPLICIT_CAMERA_KEYS)}")
    values = {key: json_field(data, key, int if key.endswith("_px") else (int, float), where)
              for key in EXPLICIT_CAMERA_KEYS}
    for key, limits in CAMERA_LIMITS.items():
        in_range(values[key], limits, f"{where}: {key}")
    try:
        return CameraPreset(name="explicit", description="explicit camera values",
                            source=where, approximate=False, **values), None
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc


def _stations(data: Any, mirror_side: str | None, where: str) -> np.ndarray:
    """(S, 2, 2) edge points from the stations list, NaN where not marked."""
    if not isinstance(data, list) or len(data) != NUM_STATIONS:
        raise InputError(f"{where}: expected a list of the {NUM_STATIONS} stations")
    edges = np.full((NUM_STATIONS, 2, 2), np.nan)
    needed = SIDE_KEYS if mirror_side is None else (SIDE_KEYS[SIDES.index(mirror_side)],)
    for idx, (entry, pct) in enumerate(zip(data, STATION_PCT.tolist())):
        at = f"{where}[{idx}]"
        if json_field(entry, "station_pct", (int, float), at) != pct:
            raise InputError(f"{at}: station_pct {entry['station_pct']!r}, expected {pct:g} "
                             f"(stations run 5, 10, … 95 in order)")
        if entry.get("skipped") is True:
            continue
        for side_idx, key in enumerate(SIDE_KEYS):
            if entry.get(key) is not None:
                edges[idx, side_idx] = _point(entry[key], f"{at}.{key}")
            elif key in needed:
                raise InputError(f"{at} ({pct:g} %): {key} missing; mark the station "
                                 f"\"skipped\": true or set mirror_side")
    return edges


def _check_inside(midline: list[np.ndarray], edges: np.ndarray, width_px: int,
                  height_px: int, where: str) -> None:
    """InputError naming the first clicked point outside the image (0 … width, 0 … height
    px): nobody can click there, so the file is wrong."""
    named = [(f"midline_px[{i}]", point) for i, point in enumerate(midline)] + [
        (f"stations ({pct:g} %) {key}", edges[idx, side])
        for idx, pct in enumerate(STATION_PCT.tolist())
        for side, key in enumerate(SIDE_KEYS) if np.isfinite(edges[idx, side]).all()]
    for name, (u, v) in named:
        if not (0 <= u <= width_px and 0 <= v <= height_px):
            raise InputError(f"{where}: {name} ({u:g}, {v:g}) lies outside the "
                             f"{width_px}×{height_px} image")


def annotation_from_json(data: Any, where: str) -> AnnotationFile:
    """Parse the JSON object of an annotation file; ``where`` names it in errors."""
    check_schema_version(data, SCHEMA_VERSION, where)
    unknown = sorted(set(data) - TOP_KEYS)
    if unknown:
        raise InputError(f"{where}: unknown keys {unknown}")
    image = json_field(data, "image", dict, where)
    camera, preset_name = _camera(json_field(data, "camera", dict, where), f"{where}: camera")
    altitude = json_field(data, "altitude", dict, where)
    altitude_m = json_field(altitude, "altitude_m", (int, float), f"{where}: altitude")
    source = json_field(altitude, "source", str, f"{where}: altitude")
    in_range(altitude_m, ALTITUDE_M, f"{where}: altitude_m")
    if source not in ALTITUDE_SOURCES:
        raise InputError(f"{where}: altitude source {source!r} is not one of "
                         f"{', '.join(ALTITUDE_SOURCES)}")
    midline = [_point(p, f"{where}: midline_px[{i}]")
               for i, p in enumerate(json_field(data, "midline_px", list, where))]
    mirror_side = data.get("mirror_side")
    if mirror_side not in (None, *SIDES):
        raise InputError(f"{where}: mirror_side must be null, \"A\" or \"B\"")
    edges = _stations(json_field(data, "stations", list, where), mirror_side, f"{where}: stations")
    _check_inside(midline, edges, camera.image_width_px, camera.image_height_px, where)
    try:
        annotation = Annotation(frame_idx=json_field(image, "frame_idx", int, f"{where}: image"),
                                midline_px=np.asarray(midline).reshape(-1, 2), edges_px=edges,
                                mirror_side=mirror_side)
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc
    return AnnotationFile(
        annotation=annotation,
        calibration=Calibration(camera, preset_name, float(altitude_m), source),
        image_id=str(image.get("image_id", "")),
        media_path=str(image.get("media_path", "")),
        notes=str(data.get("notes", "")),
    )


def annotation_to_json(doc: AnnotationFile) -> dict[str, Any]:
    """The JSON object of an annotation file (inverse of ``annotation_from_json``)."""
    ann, cal = doc.annotation, doc.calibration
    camera = ({"preset": cal.preset_name} if cal.preset_name is not None
              else {key: getattr(cal.camera, key) for key in EXPLICIT_CAMERA_KEYS})
    needed = [0, 1] if ann.mirror_side is None else [SIDES.index(ann.mirror_side)]
    stations = []
    for pct, sides in zip(STATION_PCT.tolist(), ann.edges_px):
        entry: dict[str, Any] = {"station_pct": pct}
        if np.isnan(sides[needed]).any():
            entry["skipped"] = True
        else:
            entry.update({key: None if np.isnan(side).any() else side.tolist()
                          for key, side in zip(SIDE_KEYS, sides)})
        stations.append(entry)
    return {
        "schema_version": SCHEMA_VERSION,
        "image": {"image_id": doc.image_id, "media_path": doc.media_path,
                  "frame_idx": ann.frame_idx},
        "camera": camera,
        "altitude": {"altitude_m": cal.altitude_m, "source": cal.altitude_source},
        "midline_px": ann.midline_px.tolist(),
        "mirror_side": ann.mirror_side,
        "stations": stations,
        "notes": doc.notes,
    }


def read_annotation_json(path: Path) -> AnnotationFile:
    """Read an annotation file; InputError naming the file and the faulty entry."""
    return annotation_from_json(read_json(path, "the annotation"), str(path))


def write_annotation_json(path: Path, doc: AnnotationFile) -> None:
    """Write an annotation file atomically."""
    write_json(path, annotation_to_json(doc))
