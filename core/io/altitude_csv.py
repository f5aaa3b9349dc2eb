"""Altitude tables in CSV: ``frame,altitude_m`` or ``time_s,altitude_m`` (DESIGN.md §8).

Reading: the first row names the columns; other columns are ignored; with both ``frame`` and
``time_s``, ``frame`` keys the samples. ``altitude_m`` is metres above the water surface (no
launch height is added); an empty cell, ``NaN`` or ``INVALID`` is a missing sample. Keys must
increase strictly. Writing: any columns, one row per array entry, NaN as an empty cell,
atomically.
"""

import csv
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_samples import AltitudeSamples, AltitudeSource
from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.io.text_input import cell_number, csv_rows

KEY_COLUMNS = ("frame", "time_s")  # in order of preference
ALTITUDE_COLUMN = "altitude_m"
DECIMALS = 6  # micrometres and microseconds: below any altimeter's or clock's resolution


def _rows(path: Path) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """Header and (line number, cells) of the non-blank rows; InputError if unreadable."""
    rows = csv_rows(path)
    if not rows:
        raise InputError(f"{path}: the file is empty")
    return rows[0][1], rows[1:]


def read_altitude_csv(path: Path | str) -> AltitudeSamples:
    """Altitude samples of a ``frame,altitude_m`` or ``time_s,altitude_m`` CSV file."""
    path = Path(path)
    header, rows = _rows(path)
    key = next((k for k in KEY_COLUMNS if k in header), None)
    if key is None or ALTITUDE_COLUMN not in header:
        raise InputError(f"{path}, line 1: expected columns frame,altitude_m or "
                         f"time_s,altitude_m; found {','.join(header)}")
    if not rows:
        raise InputError(f"{path}: a header but no rows")
    key_col, alt_col = header.index(key), header.index(ALTITUDE_COLUMN)
    keys, altitudes = [], []
    for line_no, cells in rows:
        if len(cells) < len(header):
            raise InputError(f"{path}, line {line_no}: {len(cells)} cells, the header has "
                             f"{len(header)}")
        value = cell_number(path, line_no, key, cells[key_col])
        if not np.isfinite(value) or (key == "frame" and (value != int(value) or value < 0)):
            raise InputError(f"{path}, line {line_no}: {key} {cells[key_col]!r} is not a valid "
                             f"{'frame index' if key == 'frame' else 'time'}")
        if keys and value <= keys[-1]:
            raise InputError(f"{path}, line {line_no}: {key} {cells[key_col]} is not greater "
                             f"than the row before ({keys[-1]:g}); rows must increase")
        keys.append(value)
        altitudes.append(cell_number(path, line_no, ALTITUDE_COLUMN, cells[alt_col]))
    source = AltitudeSource("csv", path, field=ALTITUDE_COLUMN)
    altitude_m = np.array(altitudes, dtype=np.float64)
    if key == "frame":
        return AltitudeSamples(altitude_m, source, frame_idx=np.array(keys, dtype=np.int64))
    return AltitudeSamples(altitude_m, source, time_s=np.array(keys, dtype=np.float64))


def _cell(value: float | int | bool | np.generic) -> str:
    """A CSV cell: integers as they are, floats to DECIMALS places trimmed, NaN as empty."""
    if isinstance(value, (bool, np.bool_)):
        return str(int(value))
    if isinstance(value, (int, np.integer)):
        return str(value)
    if not np.isfinite(value):
        return ""
    return np.format_float_positional(value, precision=DECIMALS, unique=True, trim="-")


def write_altitude_csv(path: Path | str, columns: Mapping[str, np.ndarray]) -> None:
    """Write ``columns`` (name → (N,) array, all the same length) as CSV, atomically."""
    path = Path(path)
    lengths = {len(values) for values in columns.values()}
    if len(lengths) != 1:
        raise ValueError(f"columns must have one length, got {sorted(lengths)}")
    with atomic_path(path) as tmp, tmp.open("w", newline="", encoding="utf-8") as file:
        writer = csv.writer(file)
        writer.writerow(columns)
        writer.writerows(zip(*([_cell(v) for v in values] for values in columns.values())))
