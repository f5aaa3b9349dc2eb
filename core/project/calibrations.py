"""A project's altitude calibrations fitted, and the one a clip's altitudes go through.

A calibration set keeps what the user measured (``core.project.model.AltitudeCalibrationSet``);
the line is fitted from it when asked (a least-squares line over at most a few hundred shots:
well under a millisecond), so a corrected click changes every result that uses it."""

from functools import lru_cache
from pathlib import Path

from core.io.calibration_table import CalibrationShot, CalibrationTable
from core.io.telemetry import Telemetry
from core.measure.altitude_calibration import (
    AltitudeCalibration,
    CalibrationCamera,
    calibrated_telemetry,
    fit_altitude_calibration,
)
from core.project.model import AltitudeCalibrationSet, ObjectShot, Project


def calibration_camera(calibration_set: AltitudeCalibrationSet) -> CalibrationCamera:
    camera = calibration_set.camera
    return CalibrationCamera(camera.focal_mm, camera.sensor_width_mm, camera.image_width_px)


@lru_cache(maxsize=64)
def fitted_calibration(calibration_set: AltitudeCalibrationSet) -> AltitudeCalibration:
    """The line of ``calibration_set``'s shots; InputError (naming the set) when they cannot
    give one (too few, too narrow a range of altitudes)."""
    nan = float("nan")
    shots = tuple(CalibrationShot(shot.image, shot.recorded_altitude_m, shot.pixel_length,
                                  nan, nan, nan, nan, calibration_set.name)
                  for shot in calibration_set.shots)
    table = CalibrationTable(Path(calibration_set.name), calibration_set.altimeter,
                             calibration_set.name, shots)
    return fit_altitude_calibration(table, calibration_set.object_length_m,
                                    calibration_camera(calibration_set))


def clip_calibration(project: Project, clip_idx: int) -> AltitudeCalibration | None:
    """The fitted calibration clip ``clip_idx``'s altitudes go through, or None."""
    name = project.clips[clip_idx].altitude_calibration
    return None if name is None else fitted_calibration(project.calibration(name))


def calibrated_clip_telemetry(project: Project, clip_idx: int,
                              telemetry: Telemetry) -> Telemetry:
    """A clip's recorded altitudes through its calibration (as they are without one);
    InputError when the calibration is of another camera."""
    calibration = clip_calibration(project, clip_idx)
    if calibration is None:
        return telemetry
    clip = project.clips[clip_idx]
    calibration.check_focal_px(clip.camera.intrinsics().focal_px, clip.media_path)
    return calibrated_telemetry(telemetry, calibration)


def shots_from_table(table: CalibrationTable) -> tuple[ObjectShot, ...]:
    """A calibration table's rows as shots of a calibration set (lengths without ends)."""
    return tuple(ObjectShot(shot.image, shot.recorded_altitude_m, shot.pixel_length)
                 for shot in table.shots)
