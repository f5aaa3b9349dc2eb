"""Reading text input files: the text, with its encoding taken from a byte-order mark, CSV
rows, and numeric cells with missing-value markers. Every failure is an InputError naming the
file and, for a cell, the line and column."""

import csv
import io
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError

# Cells meaning "no value": empty, NaN (spreadsheets, the LidarBoX logger) and INVALID (the
# LidarBoX logger before its GPS fix, reference/ecosystem.md §8). Compared in lower case.
MISSING_CELLS = frozenset({"", "nan", "invalid"})
UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")


def read_text(path: Path) -> str:
    """The file's text: UTF-16 if it starts with a UTF-16 byte-order mark, else UTF-8 (with or
    without a mark; undecodable bytes replaced)."""
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: a folder, not a file") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror})") from None
    encoding = "utf-16" if raw[:2] in UTF16_BOMS else "utf-8-sig"
    return raw.decode(encoding, errors="replace")


def csv_rows(path: Path) -> list[tuple[int, list[str]]]:
    """(row number, stripped cells) of every non-blank CSV row; InputError naming the file
    when it is no CSV (binary junk, NUL bytes)."""
    try:
        rows = [(line_no, [cell.strip() for cell in row]) for line_no, row in
                enumerate(csv.reader(io.StringIO(read_text(path))), start=1)]
    except csv.Error as exc:
        raise InputError(f"{path}: cannot be read as CSV ({exc})") from None
    return [(line_no, cells) for line_no, cells in rows if any(cells)]


def cell_number(path: Path, line_no: int, column: str, cell: str) -> float:
    """``cell`` as a float, NaN if it is a missing-value marker; InputError if not a number."""
    if cell.strip().lower() in MISSING_CELLS:
        return np.nan
    try:
        return float(cell)
    except ValueError:
        raise InputError(f"{path}, line {line_no}: {column} {cell!r} is not a number") from None


def column_positions(header: list[str], names: list[str], path: Path,
                     hint: str = "") -> dict[str, int]:
    """Where each of ``names`` sits in a table's ``header``; InputError naming the file and
    the absent columns (with ``hint`` after them) otherwise."""
    absent = [name for name in names if name not in header]
    if absent:
        raise InputError(f"{path}: the header has no {', '.join(absent)} column{hint}")
    return {name: header.index(name) for name in names}
