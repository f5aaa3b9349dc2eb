"""The tables Xcertainty's ``parse_observations`` reads (Bierlich et al. 2021; R package
Xcertainty, MMI-CODEX): one row per measured frame in the columns and order of its example
``gw_data``, and one row per calibration shot in those of its ``co_data``.

Lengths and widths are in pixels as measured, altitudes as recorded (Xcertainty fits the
altimeters' bias and the pixel error itself, from the calibration table): ``Baro_Alt`` is the
barometer's altitude with the launch height added and ``Baro_raw`` without it, ``Laser_Alt``
the laser's; a typed-in ("manual") altitude fills neither, as Xcertainty has no such
altimeter. ``year`` and ``DOY`` (day of the year) are the calendar day of the frame in the
camera's local time, as its SRT's date lines give it; empty where no date is known (no SRT,
an SRT without dates); the calibration shots' ``year`` and ``date`` are left empty.
"""

import math
from datetime import datetime

from dolphinfit.core.measure.morphometrix import number_text
from dolphinfit.core.measure.records import MeasureInput
from dolphinfit.core.measure.stations import STATION_PCT

MEASUREMENT_COLUMNS = (
    "whale_ID", "image", "year", "DOY", "uas", "Focal_Length", "Focal_Length_adj", "Sw", "Iw",
    "Baro_raw", "Launch_Ht", "Baro_Alt", "Laser_Alt", "CO.ID", "TL_px",
    *(f"TL_w{pct:05.2f}_px" for pct in STATION_PCT))
CALIBRATION_COLUMNS = (
    "uas", "CO.ID", "CO.L", "year", "image", "date", "Sw", "Iw", "Focal_Length",
    "Focal_Length_adj", "Baro_raw", "Launch_Ht", "Baro_Alt", "Laser_Alt", "Lpix")


def table_cell(value: object) -> str:
    """A value as Xcertainty's read.csv wants it: empty for none (NA), numbers in full."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return ""   # R's read.csv reads an empty numeric cell as NA
    return number_text(value) if isinstance(value, float) else str(value)


def altitude_cells(source: str, altitude_m: float, launch_height_m: float) -> dict[str, object]:
    """The altimeter's columns of a recorded altitude (launch height included)."""
    if source == "barometer":
        return {"Baro_raw": altitude_m - launch_height_m, "Launch_Ht": launch_height_m,
                "Baro_Alt": altitude_m}
    if source == "laser":
        return {"Laser_Alt": altitude_m}
    return {}


def date_cells(recorded_at: datetime | None) -> dict[str, object]:
    """``year`` and ``DOY`` (1 = 1 January) of a local date-time; none when it is unknown."""
    if recorded_at is None:
        return {}
    return {"year": recorded_at.year, "DOY": recorded_at.timetuple().tm_yday}


def observation_row(source: MeasureInput, subject: str, image: str, uas: str,
                    co_id: str | None, launch_height_m: float = 0.0,
                    recorded_at: datetime | None = None) -> dict[str, str]:
    """One measured image as a row of ``MEASUREMENT_COLUMNS``: pixels as measured, the
    altitude as recorded (before any altitude calibration), the day it was taken
    (``recorded_at``, local camera time; None: unknown)."""
    recorded = (source.record.altitude_m if source.recorded_altitude_m is None
                else source.recorded_altitude_m)
    row: dict[str, object] = {
        "whale_ID": subject, "image": image, "uas": uas,
        **date_cells(recorded_at),
        "Focal_Length": source.record.focal_mm, "Sw": source.sensor_width_mm,
        "Iw": source.image_width_px,
        **altitude_cells(source.altitude_source, recorded, launch_height_m),
        "CO.ID": co_id, "TL_px": source.pixels.length_px,
        **{f"TL_w{pct:05.2f}_px": float(width)
           for pct, width in zip(STATION_PCT, source.pixels.widths_px)}}
    return {column: table_cell(row.get(column)) for column in MEASUREMENT_COLUMNS}
