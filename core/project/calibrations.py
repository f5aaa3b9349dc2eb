"""A project's altitude calibrations fitted, and the one a clip's altitudes go through.

A calibration set keeps what the user measured (``core.project.model.AltitudeCalibrationSet``);
the line is fitted from it when asked (a least-squares line over at most a few hundred shots:
well under a millisecond), so a corrected click changes every result that uses it. Shots are
measured on image files or on frames of a video (``VIDEO#frame=N``, altitudes from its SRT).
"""

from functools import lru_cache
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.image_file import read_image
from dolphinfit.core.io.media import open_media
from dolphinfit.core.io.calibration_table import CalibrationShot, CalibrationTable
from dolphinfit.core.io.srt import parse_srt
from dolphinfit.core.io.telemetry import Telemetry, find_srt_sidecar, load_telemetry
from dolphinfit.core.measure.altitude_calibration import (
    AltitudeCalibration,
    CalibrationCamera,
    calibrated_telemetry,
    fit_altitude_calibration,
)
from dolphinfit.core.project.model import AltitudeCalibrationSet, ObjectShot, Project

UNKNOWN_ALTITUDE_M = 20.0   # a shot's altitude until the user types the recorded one


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
    calibration.check_focal_px(clip.known_camera().intrinsics().focal_px, clip.media_path)
    return calibrated_telemetry(telemetry, calibration)


def shots_from_table(table: CalibrationTable) -> tuple[ObjectShot, ...]:
    """A calibration table's rows as shots of a calibration set (lengths without ends)."""
    return tuple(ObjectShot(shot.image, shot.recorded_altitude_m, shot.pixel_length)
                 for shot in table.shots)


FRAME_MARK = "#frame="   # "clip.mp4#frame=120": a shot on a frame of a video


def read_shot_image(image: str) -> np.ndarray:
    """The RGB image a shot was measured on: an image file, or a frame of a video named
    ``VIDEO#frame=N``; InputError when it cannot be read."""
    media, mark, frame = image.partition(FRAME_MARK)
    if not mark:
        return read_image(Path(image))
    with open_media(Path(media)) as frames:
        return frames.frame(int(frame))


def srt_is_relative(video: Path) -> bool:
    """Whether the SRT beside ``video`` records height above the take-off point (False
    without one: the shots' altitudes are then typed)."""
    srt = find_srt_sidecar(video)
    return srt is not None and parse_srt(srt).family.is_relative


def clip_shots(video: Path, every: int,
               launch_height_m: float = 0.0) -> tuple[tuple[ObjectShot, ...], str]:
    """Every ``every``-th frame of a video as a shot still to be measured (a length of 1 px
    until its ends are clicked), at the altitude its SRT sidecar records there (with
    ``launch_height_m`` added to heights above the take-off point, as the clips have it); and
    a note when it has none (the altitudes are then to be typed; 20 m meanwhile, as for an
    implausible one)."""
    note = ""
    with open_media(video) as frames:
        clip = frames.clip
        try:
            altitudes = load_telemetry(clip, None, launch_height_m).altitude_m
        except InputError as exc:
            altitudes, note = np.full(clip.num_frames, np.nan), f"{exc}: type the altitudes"
    shots = tuple(ObjectShot(f"{video}{FRAME_MARK}{i}",
                             float(altitudes[i]) if np.isfinite(altitudes[i]) and altitudes[i] > 0
                             else UNKNOWN_ALTITUDE_M, 1.0)
                  for i in range(0, clip.num_frames, every))
    return shots, note
