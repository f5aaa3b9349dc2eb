"""The tables Xcertainty's ``parse_observations`` reads (Bierlich et al. 2021; R package
Xcertainty, MMI-CODEX): one row per measured frame in the columns and order of its example
``gw_data``, and one row per calibration shot in those of its ``co_data``.

Lengths and widths are in pixels as measured, altitudes as recorded (Xcertainty fits the
altimeters' bias and the pixel error itself, from the calibration table): ``Baro_Alt`` is the
barometer's altitude with the launch height added and ``Baro_raw`` without it, ``Laser_Alt``
the laser's; a typed-in ("manual") altitude fills neither, as Xcertainty has no such
altimeter. ``uas`` and ``CO.ID`` name the clip's altitude calibration where it has one (its
shots are the training objects of that drone), else the camera. Dates are not kept by
dolphinfit and are left empty.
"""

import math

from core.measure.morphometrix import number_text
from core.measure.stations import STATION_PCT
from core.project.model import ClipEntry, Project
from core.project.results import FrameResult

MEASUREMENT_COLUMNS = (
    "whale_ID", "image", "year", "DOY", "uas", "Focal_Length", "Focal_Length_adj", "Sw", "Iw",
    "Baro_raw", "Launch_Ht", "Baro_Alt", "Laser_Alt", "CO.ID", "TL_px",
    *(f"TL_w{pct:05.2f}_px" for pct in STATION_PCT))
CALIBRATION_COLUMNS = (
    "uas", "CO.ID", "CO.L", "year", "image", "date", "Sw", "Iw", "Focal_Length",
    "Focal_Length_adj", "Baro_raw", "Launch_Ht", "Baro_Alt", "Laser_Alt", "Lpix")


def _cell(value: object) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return ""   # R's read.csv reads an empty numeric cell as NA
    return number_text(value) if isinstance(value, float) else str(value)


def _altitudes(source: str, altitude_m: float, launch_height_m: float) -> dict[str, object]:
    if source == "barometer":
        return {"Baro_raw": altitude_m - launch_height_m, "Launch_Ht": launch_height_m,
                "Baro_Alt": altitude_m}
    if source == "laser":
        return {"Laser_Alt": altitude_m}
    return {}


def _drone(clip: ClipEntry) -> str:
    return clip.altitude_calibration or clip.preset_name or clip.camera.name


def measurement_row(project: Project, result: FrameResult) -> dict[str, str]:
    """One measured frame as a row of ``MEASUREMENT_COLUMNS``."""
    clip = project.clips[result.key.clip]
    source, measured = result.source, result.estimate.measured
    recorded = (source.record.altitude_m if source.recorded_altitude_m is None
                else source.recorded_altitude_m)
    launch = clip.altitude.launch_height_m if clip.altitude is not None else 0.0
    row: dict[str, object] = {
        "whale_ID": clip.animals[result.key.animal].animal_id, "image": result.image_id,
        "uas": _drone(clip), "Focal_Length": clip.camera.focal_mm,
        "Sw": clip.camera.sensor_width_mm, "Iw": clip.camera.image_width_px,
        **_altitudes(source.altitude_source, recorded, launch),
        "CO.ID": clip.altitude_calibration, "TL_px": measured.length_px,
        **{f"TL_w{pct:05.2f}_px": float(width)
           for pct, width in zip(STATION_PCT, measured.widths_px)}}
    return {column: _cell(row.get(column)) for column in MEASUREMENT_COLUMNS}


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
                   **_altitudes(calibration.altimeter, shot.recorded_altitude_m, 0.0),
                   "Lpix": shot.pixel_length}
            if calibration.altimeter == "barometer":
                del row["Baro_raw"], row["Launch_Ht"]   # only the sum was recorded with a shot
            rows.append({column: _cell(row.get(column)) for column in CALIBRATION_COLUMNS})
    return rows
