"""Laser-altimeter logs in the LidarBoX style.

The format follows the description in reference/ecosystem.md §8 (no real log ships with the
project): the Dawson / LidarBoX Arduino logger (LightWare SF11/C laser, GPS, IMU; Bierlich et
al. 2024, doi:10.1139/dsa-2023-0051) writes tab-separated text at about 1 Hz, often named
``LOG_0000.CSV``. Comment lines start with ``#``; the last one before the data is the header

    #gmt_date  gmt_time  num_sats  longitude  latitude  gps_altitude_m  SOG_kt  COG  HDOP
    laser_altitude_cm  tilt_deg  accel_x  accel_y  accel_z  gyro_x  gyro_y  gyro_z

with dates ``YYYY/MM/DD`` and times ``HH:MM:SS`` (UTC from the GPS; ``INVALID`` before a fix),
the laser distance in centimetres and missing values written ``NaN`` or ``INVALID``.

Altitude = laser_altitude_cm / 100 × cos(tilt_deg): the laser is fixed to the airframe, so a
tilted airframe measures a slant range (CollatriX v2, Whalength); a gimballed laser needs no
correction. 13000 and 15000 cm are the SF11's error readings (CollatriX v2) and count as
missing. The laser measures height above the water directly: no launch height is added.

Time alignment: ``time_offset_s`` is the log time, in seconds after the log's first dated row,
at which the clip's first frame was recorded; a row's time on the clip's clock is its log time
minus ``time_offset_s``. Filming a GPS clock (the log's own UTC time base) gives it:
``gps_clock_offset_s``.
"""

import math
from datetime import datetime
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_samples import AltitudeSamples, AltitudeSource
from dolphinfit.core.io.report import list_some
from dolphinfit.core.io.text_input import cell_number, column_positions, read_text

LASER_COLUMN = "laser_altitude_cm"
TILT_COLUMN = "tilt_deg"
DATE_COLUMN, TIME_COLUMN = "gmt_date", "gmt_time"
ERROR_VALUES_CM = frozenset({13000.0, 15000.0})  # SF11 error readings (CollatriX v2)
CM_PER_M = 100.0
MAX_TILT_DEG = 90.0  # beyond this the laser cannot point at the water
TIME_FORMATS = ("%Y/%m/%d %H:%M:%S", "%Y/%m/%d %H:%M:%S.%f")


def _cells(line: str) -> list[str]:
    """A row's cells: tab-separated, or whitespace-separated if the line has no tab."""
    return [c.strip() for c in (line.split("\t") if "\t" in line else line.split())]


def _header_and_rows(path: Path) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """The header's column names and the (line number, cells) of the data rows."""
    lines = read_text(path).splitlines()
    header = None
    rows = []
    for line_no, line in enumerate(lines, start=1):
        if line.startswith("#"):
            if LASER_COLUMN in line:
                header = _cells(line.lstrip("#"))
        elif line.strip():
            rows.append((line_no, _cells(line)))
    if header is None:
        raise InputError(f"{path}: no '#' header line naming {LASER_COLUMN} "
                         "(not a LidarBoX laser log?)")
    return header, rows


def _row_time(date: str, time: str) -> datetime | None:
    """The row's UTC date-time, or None if the logger wrote INVALID (no GPS fix yet)."""
    for time_format in TIME_FORMATS:
        try:
            return datetime.strptime(f"{date} {time}", time_format)
        except ValueError:
            continue
    return None


def read_laser_log(path: Path | str, time_offset_s: float = 0.0,
                   tilt_correction: bool = True) -> AltitudeSamples:
    """Altitude samples of a LidarBoX-style laser log, on the clip's clock.

    Error readings (13000, 15000 cm), missing readings and, with ``tilt_correction``, missing
    or impossible tilts give NaN samples; rows without a valid date and time, short rows and
    rows not later than the row before are dropped. Each case adds one warning naming the
    lines. ``tilt_correction=False`` is for a gimballed laser.
    """
    path = Path(path)
    header, rows = _header_and_rows(path)
    needed = [DATE_COLUMN, TIME_COLUMN, LASER_COLUMN] + ([TILT_COLUMN] if tilt_correction else [])
    only_tilt_absent = [c for c in needed if c not in header] == [TILT_COLUMN]
    col = column_positions(header, needed, path, " (a gimballed laser needs no tilt "
                           "correction)" if only_tilt_absent else "")
    problems: dict[str, list[int]] = {}
    times, altitudes = [], []
    for line_no, cells in rows:
        if len(cells) < len(header):
            problems.setdefault("short row, dropped", []).append(line_no)
            continue
        when = _row_time(cells[col[DATE_COLUMN]], cells[col[TIME_COLUMN]])
        if when is None:
            problems.setdefault("no valid date and time, dropped", []).append(line_no)
            continue
        if times and when <= times[-1]:
            problems.setdefault("not later than the row before, dropped", []).append(line_no)
            continue
        laser_cm = cell_number(path, line_no, LASER_COLUMN, cells[col[LASER_COLUMN]])
        if laser_cm in ERROR_VALUES_CM:
            problems.setdefault("laser error reading (13000/15000 cm)", []).append(line_no)
            laser_cm = np.nan
        elif not laser_cm > 0:
            problems.setdefault("no laser reading", []).append(line_no)
            laser_cm = np.nan
        factor = 1.0
        if tilt_correction:
            tilt = cell_number(path, line_no, TILT_COLUMN, cells[col[TILT_COLUMN]])
            factor = math.cos(math.radians(tilt)) if abs(tilt) < MAX_TILT_DEG else np.nan
            if np.isnan(factor):
                problems.setdefault("no valid tilt", []).append(line_no)
        times.append(when)
        altitudes.append(laser_cm / CM_PER_M * factor)
    if not times:
        raise InputError(f"{path}: no row with a valid date and time")
    time_s = np.array([(t - times[0]).total_seconds() for t in times]) - time_offset_s
    warnings = tuple(f"{path}, lines {list_some([str(n) for n in lines])}: {what}"
                     for what, lines in problems.items())
    source = AltitudeSource("laser", path, "lidarbox", LASER_COLUMN,
                            time_offset_s=time_offset_s)
    return AltitudeSamples(np.array(altitudes), source, time_s=time_s, warnings=warnings)


def log_start(path: Path | str) -> datetime:
    """The UTC date-time of the log's first dated row."""
    path = Path(path)
    header, rows = _header_and_rows(path)
    col = column_positions(header, [DATE_COLUMN, TIME_COLUMN], path)
    date_col, time_col = col[DATE_COLUMN], col[TIME_COLUMN]
    for _, cells in rows:
        if len(cells) >= len(header):   # as read_laser_log: a short row is dropped
            when = _row_time(cells[date_col], cells[time_col])
            if when is not None:
                return when
    raise InputError(f"{path}: no row with a valid date and time")


def parse_clock_time(text: str, what: str) -> datetime:
    """A GPS clock's reading, ``YYYY/MM/DD HH:MM:SS[.f]`` (or with dashes), UTC; InputError
    naming ``what`` otherwise."""
    for time_format in (*TIME_FORMATS, "%Y-%m-%d %H:%M:%S", "%Y-%m-%d %H:%M:%S.%f"):
        try:
            return datetime.strptime(text.strip(), time_format)
        except ValueError:
            continue
    raise InputError(f"{what} {text!r}: expected a UTC date and time as YYYY/MM/DD HH:MM:SS "
                     "(seconds may have decimals)")


def gps_clock_offset_s(path: Path | str, clock: datetime, video_time_s: float) -> float:
    """The ``time_offset_s`` of a clip in which a GPS clock reads ``clock`` (UTC) at
    ``video_time_s`` seconds into the clip: the clip's first frame was recorded at
    ``clock - video_time_s``, that many seconds after the log's first dated row. InputError
    when the clock reading lies more than a day from the log."""
    path = Path(path)
    start = log_start(path)
    offset = (clock - start).total_seconds() - video_time_s
    if abs(offset) > 86_400:
        raise InputError(f"{path}: the GPS clock's {clock:%Y/%m/%d %H:%M:%S} lies more than a "
                         f"day from the log's start ({start:%Y/%m/%d %H:%M:%S}): "
                         "another day's log or clip?")
    return offset


def is_laser_log(path: Path) -> bool:
    """Whether the file's comment lines name the laser column (a LidarBoX log, any suffix)."""
    try:
        with path.open(encoding="utf-8", errors="replace") as file:
            for line in file:
                if not line.startswith("#"):
                    return False
                if LASER_COLUMN in line:
                    return True
    except OSError:
        return False
    return False
