"""Freefly Astro flight logs: the camera's laser range on the video's own clock.

The format follows reference/ecosystem.md §8 (CollatriX v2's "Wrangle Astro"; no real log
ships with the project): a CSV with a header row naming, among others, ``Unix Time (ms)``,
``Video Time (s)``, ``Altitude (m above takeoff location)`` and ``Camera Range (m)``.
``Camera Range (m)`` is the laser rangefinder's distance along the camera's axis, which is
the height above the water for a camera pointing straight down; ``0.00`` is its error
reading. ``Video Time (s)`` places each row on the clip's clock, so no clock needs aligning;
rows without one (the camera not recording) are dropped. ``time_offset_s``, where given,
shifts the rows as for a laser log (laser_log.py): a row's time on the clip's clock is its
video time minus the offset.
"""

import csv
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_samples import AltitudeSamples, AltitudeSource
from dolphinfit.core.io.report import list_some
from dolphinfit.core.io.text_input import cell_number, column_positions, read_text

RANGE_COLUMN = "Camera Range (m)"
VIDEO_TIME_COLUMN = "Video Time (s)"


def _rows(path: Path) -> tuple[list[str], list[tuple[int, list[str]]]]:
    lines = read_text(path).splitlines()
    table = list(csv.reader(lines))
    if not table:
        raise InputError(f"{path}: empty")
    header = [name.strip() for name in table[0]]
    return header, [(n, cells) for n, cells in enumerate(table[1:], start=2) if any(cells)]


def is_astro_log(path: Path) -> bool:
    """Whether the file's first line names the Astro's range and video-time columns."""
    try:
        with path.open(encoding="utf-8", errors="replace") as file:
            first = file.readline()
    except OSError:
        return False
    return RANGE_COLUMN in first and VIDEO_TIME_COLUMN in first


def read_astro_log(path: Path | str, time_offset_s: float = 0.0) -> AltitudeSamples:
    """Altitude samples of a Freefly Astro log on the clip's clock (module doc). Error
    readings give NaN samples; rows without a video time, short rows and rows not later than
    the row before are dropped; each case adds one warning naming the lines."""
    path = Path(path)
    header, rows = _rows(path)
    col = column_positions(header, [VIDEO_TIME_COLUMN, RANGE_COLUMN], path)
    time_col, range_col = col[VIDEO_TIME_COLUMN], col[RANGE_COLUMN]
    problems: dict[str, list[int]] = {}
    times: list[float] = []
    altitudes: list[float] = []
    for line_no, cells in rows:
        if len(cells) <= max(time_col, range_col):
            problems.setdefault("short row, dropped", []).append(line_no)
            continue
        when = cell_number(path, line_no, VIDEO_TIME_COLUMN, cells[time_col])
        if not np.isfinite(when):
            problems.setdefault("not recording (no video time), dropped", []).append(line_no)
            continue
        if times and when <= times[-1]:
            problems.setdefault("not later than the row before, dropped", []).append(line_no)
            continue
        distance = cell_number(path, line_no, RANGE_COLUMN, cells[range_col])
        if not distance > 0:
            problems.setdefault("laser error reading (0.00 m) or none", []).append(line_no)
            distance = np.nan
        times.append(when)
        altitudes.append(distance)
    if not times:
        raise InputError(f"{path}: no row with a video time (was the camera recording?)")
    warnings = tuple(f"{path}, lines {list_some([str(n) for n in lines])}: {what}"
                     for what, lines in problems.items())
    source = AltitudeSource("laser", path, "freefly-astro", RANGE_COLUMN,
                            time_offset_s=time_offset_s)
    return AltitudeSamples(np.array(altitudes), source,
                           time_s=np.array(times) - time_offset_s, warnings=warnings)
