"""What an animal's 3D fit was made from (its clip's camera, altitude, altitude calibration,
lens and masks), kept beside the fit so that a fit made before one of them changed says so:
after a calibration the elliptical volume of a clip dropped to a third, and the comparison
set it against the old fit as "+192 %"."""

import hashlib
import json
from pathlib import PurePosixPath

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.project.model import Animal, ClipEntry, Project

INPUT_NAMES = {"camera": "camera", "altitude": "altitude", "calibration": "altitude calibration",
               "lens": "lens", "masks": "masks"}


def _digest(value: object) -> str:
    """A short digest of ``value`` (numbers, strings, None and sequences of them)."""
    return hashlib.sha1(json.dumps(value).encode()).hexdigest()[:12]


def _camera(camera: CameraPreset) -> list:
    """What of a camera a measurement uses (not its name or description)."""
    return [camera.focal_mm, camera.sensor_width_mm, camera.image_width_px,
            camera.image_height_px]


def _file(path: str | None) -> str | None:
    """A file by its name: Save As and a moved project rebase the relative paths."""
    return None if path is None else PurePosixPath(path).name


def _inputs(project: Project, clip: ClipEntry) -> dict[str, object]:
    """The clip's inputs to a fit as plain values (``INPUT_NAMES``)."""
    altitude, lens = clip.altitude, clip.lens
    calibration = next((c for c in project.calibrations
                        if c.name == clip.altitude_calibration), None)
    return {
        "camera": None if clip.camera is None else _camera(clip.camera),
        "altitude": None if altitude is None else [
            _file(altitude.path), altitude.constant_m, altitude.launch_height_m,
            altitude.time_offset_s, altitude.source],
        "calibration": None if calibration is None else [
            calibration.object_length_m, calibration.altimeter, _camera(calibration.camera),
            [[shot.recorded_altitude_m, shot.pixel_length] for shot in calibration.shots]],
        "lens": None if lens is None else [
            lens.width_px, lens.height_px, lens.fx_px, lens.fy_px, lens.cx_px, lens.cy_px,
            list(lens.distortion)],
        "masks": _file(clip.masks_path)}


def fit_inputs_of(project: Project, clip: ClipEntry) -> tuple[tuple[str, str], ...]:
    """The digest of each of the clip's inputs to a fit (``INPUT_NAMES``), as pairs."""
    return tuple((name, _digest(value)) for name, value in _inputs(project, clip).items())


def changed_since_fit(project: Project, clip: ClipEntry, animal: Animal) -> list[str]:
    """The inputs (in words) that differ now from those the animal's fit was made from;
    empty where it has no fit, or a fit from before inputs were kept."""
    if animal.fit_path is None or not animal.fit_inputs:
        return []
    then = dict(animal.fit_inputs)
    return [INPUT_NAMES[name] for name, digest in fit_inputs_of(project, clip)
            if name in then and then[name] != digest]


def stale_note(changed: list[str]) -> str:
    """One line saying the fit is out of date and what to do, or "" when it is not."""
    if not changed:
        return ""
    return (f"⚠ out of date: the clip's {', '.join(changed)} changed since this fit; its "
            "figures are not comparable: fit again")
