"""A project's measured frames and calibration shots as Xcertainty's tables (the columns and
what goes in them: core.measure.xcertainty). ``uas`` and ``CO.ID`` name the clip's altitude
calibration where it has one (its shots are the training objects of that drone), else the
camera. ``whale_ID`` is one animal across the project: the numbers dolphinfit gives
("dolphin 1") count within a clip, so they go out after the clip's name; a name a person
gave (a catalogue ID) goes out as given, so that the same individual in several clips is
one animal to Xcertainty. ``year`` and ``DOY`` come from the frame's date
(FrameResult.recorded_at, read from the clip's SRT when it was measured)."""

import re
from pathlib import Path

from dolphinfit.core.measure.xcertainty import (
    CALIBRATION_COLUMNS, altitude_cells, observation_row, table_cell,
)
from dolphinfit.core.project.model import ClipEntry, Project
from dolphinfit.core.project.results import FrameResult

NUMBERED_ANIMAL = re.compile(r"dolphin \d+")   # the IDs the app and the scan give


def _drone(clip: ClipEntry) -> str:
    return clip.altitude_calibration or clip.preset_name or clip.known_camera().name


def measurement_row(project: Project, result: FrameResult) -> dict[str, str]:
    """One measured frame as a row of ``MEASUREMENT_COLUMNS``."""
    clip = project.clips[result.key.clip]
    launch = clip.altitude.launch_height_m if clip.altitude is not None else 0.0
    animal_id = clip.animals[result.key.animal].animal_id
    return observation_row(result.source, subject_id(clip, animal_id), result.image_id,
                           _drone(clip), clip.altitude_calibration, launch, result.recorded_at)


def subject_id(clip: ClipEntry, animal_id: str) -> str:
    """The animal's ``whale_ID`` (module doc)."""
    if NUMBERED_ANIMAL.fullmatch(animal_id):
        return f"{Path(clip.media_path).stem} {animal_id}"
    return animal_id


def calibration_rows(project: Project) -> list[dict[str, str]]:
    """Every shot of the project's altitude calibrations as rows of ``CALIBRATION_COLUMNS``
    (the object's length in metres, ``Lpix`` its pixel length)."""
    rows = []
    for calibration in project.calibrations:
        camera = calibration.camera
        for shot in calibration.shots:
            row = {"uas": calibration.name, "CO.ID": calibration.name,
                   "CO.L": calibration.object_length_m, "image": shot.image,
                   "Sw": camera.sensor_width_mm, "Iw": camera.image_width_px,
                   "Focal_Length": camera.focal_mm,
                   **altitude_cells(calibration.altimeter, shot.recorded_altitude_m, 0.0),
                   "Lpix": shot.pixel_length}
            if calibration.altimeter == "barometer":
                del row["Baro_raw"], row["Launch_Ht"]   # only the sum was recorded with a shot
            rows.append({column: table_cell(row.get(column)) for column in CALIBRATION_COLUMNS})
    return rows
