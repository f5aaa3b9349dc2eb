"""MedidoR measurement spreadsheets (``Measurements_10.xlsx``, ``Measurements_05.xlsx``).

MedidoR (de Oliveira et al., R/Shiny) saves one row per measured image: the drone, image and
altitudes (``TO_Alt`` take-off, ``F_Alt`` flight, ``C_Alt`` their sum, ``Laser_Alt``), the
camera (``sw`` sensor width mm, ``iw`` image width px, ``flen`` focal length mm), the body
length ``BL`` and the widths ``WD_<percent>`` in pixels, the fluke span ``WD_F`` in pixels, and
``cGSD``, the metres per pixel it applied (from its calibration when one was loaded), with
``EstLength`` = ``BL`` × ``cGSD``. Its geometry is ``core.measure.annotation.MEDIDOR``.
"""

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError

REQUIRED = ("ID", "imid", "BL", "C_Alt", "sw", "iw", "flen", "cGSD")
WIDTH_COLUMN = re.compile(r"^WD_(?P<pct>\d+(?:\.\d*)?)$")
FLUKE_COLUMN = "WD_F"


@dataclass(frozen=True)
class MedidorRow:
    """One measured image of a MedidoR spreadsheet; pixels as MedidoR measured them."""

    image_id: str
    image_name: str
    altitude_m: float            # C_Alt: take-off plus flight altitude
    sensor_width_mm: float
    image_width_px: int
    focal_mm: float
    length_px: float
    widths_px: dict[float, float]  # percent of body length → width, px
    fluke_span_px: float         # NaN when not measured
    gsd_m_per_px: float          # cGSD: what MedidoR applied


def _sheet_rows(path: Path) -> list[tuple]:
    """The first sheet's rows as tuples of cell values; InputError if it is no workbook."""
    import openpyxl  # only the readers of spreadsheets pay for it

    try:
        workbook = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except Exception as exc:  # openpyxl raises zipfile, KeyError and its own errors
        raise InputError(f"{path}: cannot be read as an .xlsx workbook ({exc})") from None
    try:
        return [tuple(row) for row in workbook.worksheets[0].iter_rows(values_only=True)]
    finally:
        workbook.close()


def _number(path: Path, row_no: int, column: str, value: object) -> float:
    if value is None or value == "":
        return float("nan")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{path}, row {row_no}: {column} {value!r} is not a number") from None
    return number


def _positive(path: Path, row_no: int, column: str, value: object) -> float:
    number = _number(path, row_no, column, value)
    if not (np.isfinite(number) and number > 0):
        raise InputError(f"{path}, row {row_no}: {column} must be a positive number, "
                         f"got {value!r}")
    return number


def read_medidor(path: Path) -> list[MedidorRow]:
    """Every measured image of a MedidoR spreadsheet, in file order.

    InputError naming the file (and row and column) when it is no workbook, lacks one of
    ``REQUIRED`` columns or a width column, or a number is missing or not positive.
    """
    rows = _sheet_rows(path)
    if not rows:
        raise InputError(f"{path}: the sheet is empty")
    header = [str(cell).strip() if cell is not None else "" for cell in rows[0]]
    missing = [name for name in REQUIRED if name not in header]
    if missing:
        raise InputError(f"{path}: not a MedidoR measurement sheet (no column "
                         f"{', '.join(missing)})")
    widths = {float(match["pct"]): index for index, name in enumerate(header)
              if (match := WIDTH_COLUMN.match(name))}
    if not widths:
        raise InputError(f"{path}: no width columns (WD_10, WD_20, …)")
    column = {name: index for index, name in enumerate(header)}
    records = []
    for row_no, cells in enumerate(rows[1:], start=2):
        if all(cell is None for cell in cells):
            continue
        cell = dict(zip(header, cells))
        fluke = cells[column[FLUKE_COLUMN]] if FLUKE_COLUMN in column else None
        records.append(MedidorRow(
            image_id=str(cell["ID"]), image_name=str(cell["imid"]),
            altitude_m=_positive(path, row_no, "C_Alt", cell["C_Alt"]),
            sensor_width_mm=_positive(path, row_no, "sw", cell["sw"]),
            image_width_px=int(_positive(path, row_no, "iw", cell["iw"])),
            focal_mm=_positive(path, row_no, "flen", cell["flen"]),
            length_px=_positive(path, row_no, "BL", cell["BL"]),
            widths_px={pct: _number(path, row_no, header[index], cells[index])
                       for pct, index in sorted(widths.items())},
            fluke_span_px=_number(path, row_no, FLUKE_COLUMN, fluke),
            gsd_m_per_px=_positive(path, row_no, "cGSD", cell["cGSD"])))
    if not records:
        raise InputError(f"{path}: no measured image in the sheet")
    return records
