"""MorphoMetriX measurement CSVs: read and write v1 (blocks) and v2 (long).

Formats (reference/ecosystem.md §6.1, the real files in tests/data/morphometrix/):

- **v2, long**: columns ``Object,Value,Value_unit``. Metadata rows (``Value_unit`` =
  ``Metadata``): Image ID, Image Path, Focal Length (mm), Altitude (m), Pixel Dimension (mm/px
  = sensor width / image width), Mirror Side (None, A or B), Notes. Then every measurement in
  ``Meters`` (``Square Meters``, ``Degrees``) and again in ``Pixels``. Widths are named
  ``<length>_w<percent>``; MorphoMetriX mixes ``TL_w10.00`` and ``TL_w10.0``, so names are
  normalised to CollatriX's zero-padded form ``TL_w10.00`` / ``TL_w05.00`` on reading and
  written that way. An area's pixel row is in square pixels.
- **v1, blocks**: ``key,value`` metadata rows; an ``Object,Length (m),…`` block whose width
  columns are headed ``10.00% Width`` (on the header row or on the row below it), one row per
  length in metres; then ``Object,Angle`` and ``Object,Area (m²)`` blocks. Metres only.
  Some v1 files head the blocks ``Object Name,Length,…`` instead. v1 has no Mirror Side row.

Each lab names the total length as it likes (``TL``, ``Total_Length``, ``Total Length`` in the
real files); :func:`total_length_name` finds it whatever its case, spaces and underscores.
Our files name it ``TL``, as MorphoMetriX v2 and CollatriX do.

Scale: metres per pixel = pixel dimension (mm/px) × altitude (m) / focal length (mm), the same
as altitude / focal_px.
"""

import csv
import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.io.text_input import MISSING_CELLS, cell_number, csv_rows
from dolphinfit.core.limits import (
    ALTITUDE_M, FOCAL_MM, PIXEL_DIMENSION_MM, body_measurements, in_range,
)
from dolphinfit.core.measure.annotation import PixelMeasurements
from dolphinfit.core.measure.stations import STATION_PCT

LENGTH_NAME = "TL"  # MorphoMetriX / CollatriX name of total length (rostrum tip to fluke notch)
# total length as labs name it, normalised (_normalised_name): TL, Total_Length, Body length, …
TOTAL_LENGTH_NAMES = frozenset({"tl", "totallength", "bodylength"})
MMX_VERSIONS = (1, 2)
V2_HEADER = ["Object", "Value", "Value_unit"]
METADATA = "Metadata"
METERS, PIXELS = "Meters", "Pixels"
SQUARE_METERS, SQUARE_PIXELS, DEGREES = "Square Meters", "Square Pixels", "Degrees"
# Metadata row name → MorphoMetrixRecord field (v1 and v2 share the names)
METADATA_FIELDS = {"Image ID": "image_id", "Image Path": "image_path",
                   "Focal Length": "focal_mm", "Altitude": "altitude_m",
                   "Pixel Dimension": "pixel_dimension_mm", "Mirror Side": "mirror_side",
                   "Notes": "notes"}
NUMERIC_FIELDS = {"focal_mm": FOCAL_MM, "altitude_m": ALTITUDE_M,
                  "pixel_dimension_mm": PIXEL_DIMENSION_MM}  # and their plausible ranges
WIDTH_NAME = re.compile(r"^(?P<length>.+)_w(?P<pct>\d+(?:\.\d*)?)$")
V1_BLOCK_HEADS = ("Object", "Object Name")  # both in MorphoMetriX v1's own demo files
V1_WIDTH_HEADER = re.compile(r"^(?P<pct>\d+(?:\.\d*)?)\s*%\s*Width$")
V1_METADATA = ("Image ID", "Image Path", "Focal Length", "Altitude", "Pixel Dimension", "Notes")
V1_LENGTH_HEAD = ["Object", "Length (m)"]
V1_OTHER_HEADS = {DEGREES: ["Object", "Angle"], SQUARE_METERS: ["Object", "Area (m²)"]}


@dataclass(frozen=True)
class MorphoMetrixRecord:
    """The measurements of one MorphoMetriX CSV (one image).

    Widths are keyed by their length's name, then by percent of that length. ``others``
    holds angles and areas as (object, value, unit). v1 files have no pixel values.
    """

    version: int
    image_id: str
    image_path: str
    focal_mm: float
    altitude_m: float
    pixel_dimension_mm: float
    mirror_side: str | None
    notes: str
    lengths_m: dict[str, float] = field(default_factory=dict)
    lengths_px: dict[str, float] = field(default_factory=dict)
    widths_m: dict[str, dict[float, float]] = field(default_factory=dict)
    widths_px: dict[str, dict[float, float]] = field(default_factory=dict)
    others: tuple[tuple[str, float, str], ...] = ()

    @property
    def m_per_px(self) -> float:
        """Metres per pixel: pixel dimension × altitude / focal length."""
        return self.pixel_dimension_mm * self.altitude_m / self.focal_mm

    @property
    def focal_px(self) -> float:
        """Focal length in pixels: focal length / pixel dimension."""
        return self.focal_mm / self.pixel_dimension_mm


def width_name(length_name: str, pct: float) -> str:
    """CollatriX's width name, e.g. ``TL_w05.00`` for 5 % of ``TL``."""
    return f"{length_name}_w{pct:05.2f}"


def _normalised_name(name: str) -> str:
    """A length's name without case, spaces, underscores or hyphens: ``Total_Length`` →
    ``totallength``."""
    return re.sub(r"[\s_-]+", "", name).casefold()


def total_length_name(record: MorphoMetrixRecord, path: Path,
                      length_name: str | None = None) -> str:
    """The record's name of the total length: ``length_name`` if given, else one of
    TOTAL_LENGTH_NAMES, either matched whatever its case, spaces and underscores.

    InputError naming ``path`` and the file's lengths when none or several match.
    """
    wanted = (TOTAL_LENGTH_NAMES if length_name is None
              else frozenset({_normalised_name(length_name)}))
    names = list(dict.fromkeys([*record.lengths_px, *record.lengths_m]))
    found = [name for name in names if _normalised_name(name) in wanted]
    if len(found) == 1:
        return found[0]
    what = (f"no length named {length_name!r}" if length_name is not None and not found
            else "no total length (TL, Total_Length, Total Length …)" if not found
            else f"several total lengths ({', '.join(found)})")
    raise InputError(f"{path}: {what} among its lengths ({', '.join(names) or 'none'}); "
                     f"name the one to use with --length-name")


def _float(text: str, path: Path, line_no: int, what: str) -> float:
    """A cell that must hold a number (not empty, not NaN); InputError naming file and line."""
    value = cell_number(path, line_no, what, text)
    if not math.isfinite(value):
        raise InputError(f"{path}, line {line_no}: {what} {text!r} is not a number")
    return value


def _metadata(pairs: dict[str, tuple[int, str]], path: Path) -> dict[str, object]:
    """Record fields from metadata rows {name: (line, value)}; numbers checked."""
    meta: dict[str, object] = {"image_id": "", "image_path": "", "mirror_side": None,
                               "notes": ""}
    for name, (line_no, value) in pairs.items():
        key = METADATA_FIELDS.get(name)
        if key in NUMERIC_FIELDS:
            meta[key] = in_range(_float(value, path, line_no, name), NUMERIC_FIELDS[key],
                                 f"{path}, line {line_no}: {name}")
        elif key == "mirror_side":
            meta[key] = None if value in ("", "None") else value
        elif key is not None:
            meta[key] = value
    missing = [name for name, key in METADATA_FIELDS.items()
               if key in NUMERIC_FIELDS and key not in meta]
    if missing:
        raise InputError(f"{path}: metadata {', '.join(missing)} missing; metres cannot be "
                         f"related to pixels")
    return meta


def _split_width(name: str) -> tuple[str, float] | None:
    """(length name, percent) of a width name such as ``TL_w10.0``; None otherwise."""
    match = WIDTH_NAME.match(name)
    return (match["length"], float(match["pct"])) if match else None


def _read_v2(rows: list[tuple[int, list[str]]], path: Path) -> MorphoMetrixRecord:
    """Parse the long format (rows after the header)."""
    pairs, kind_of, measured = {}, {}, []
    for line_no, cells in rows:
        if len(cells) < 3:
            raise InputError(f"{path}, line {line_no}: expected Object,Value,Value_unit")
        name, value, unit = cells[:3]
        if unit == METADATA:
            pairs[name] = (line_no, value)
        elif unit in (METERS, PIXELS, SQUARE_METERS, DEGREES):
            kind_of.setdefault(name, unit)  # the metre section, first, tells areas from lengths
            measured.append((name, _float(value, path, line_no, name), unit))
        else:
            raise InputError(f"{path}, line {line_no}: unknown unit {unit!r}")
    lengths = {METERS: {}, PIXELS: {}}
    widths = {METERS: {}, PIXELS: {}}
    others = {}
    for name, number, unit in measured:
        width = _split_width(name)
        if kind_of[name] == DEGREES:
            others.setdefault((name, DEGREES), number)  # angles repeat in both sections
        elif kind_of[name] == SQUARE_METERS:
            others[(name, SQUARE_PIXELS if unit == PIXELS else unit)] = number
        elif width is not None:
            widths[unit].setdefault(width[0], {})[width[1]] = number
        else:
            lengths[unit][name] = number
    return MorphoMetrixRecord(
        version=2, lengths_m=lengths[METERS], lengths_px=lengths[PIXELS],
        widths_m=widths[METERS], widths_px=widths[PIXELS],
        others=tuple((name, value, unit) for (name, unit), value in others.items()),
        **_metadata(pairs, path))


def _read_v1(rows: list[tuple[int, list[str]]], path: Path) -> MorphoMetrixRecord:
    """Parse the block format."""
    pairs, block, width_columns = {}, "metadata", {}
    lengths, widths, others = {}, {}, []
    for line_no, cells in rows:
        first, second = cells[0], (cells + [""])[1]
        if first in V1_BLOCK_HEADS:
            block = second.split(" ")[0].lower()
            if block not in ("length", "angle", "area"):
                raise InputError(f"{path}, line {line_no}: unknown block {second!r}")
            width_columns = _v1_width_columns(cells) if block == "length" else {}
        elif block == "metadata":
            pairs[first] = (line_no, second)
        elif block == "length" and not first:
            width_columns = _v1_width_columns(cells)
        elif block == "length":
            lengths[first] = _float(second, path, line_no, first)
            widths[first] = {pct: _float(cells[col], path, line_no, f"{first} {pct:g}% width")
                             for col, pct in width_columns.items()
                             if col < len(cells) and cells[col].lower() not in MISSING_CELLS}
        else:
            unit = DEGREES if block == "angle" else SQUARE_METERS
            others.append((first, _float(second, path, line_no, first), unit))
    return MorphoMetrixRecord(version=1, lengths_m=lengths,
                              widths_m={k: v for k, v in widths.items() if v},
                              others=tuple(others), **_metadata(pairs, path))


def _v1_width_columns(cells: list[str]) -> dict[int, float]:
    """{column: percent} of the ``10.00% Width`` headers in a row."""
    return {col: float(match["pct"]) for col, cell in enumerate(cells)
            if (match := V1_WIDTH_HEADER.match(cell))}


def read_morphometrix(path: Path) -> MorphoMetrixRecord:
    """Read a MorphoMetriX v1 or v2 CSV (told apart by the first row)."""
    path = Path(path)
    rows = csv_rows(path)
    if rows and rows[0][1][:3] == V2_HEADER:
        return _read_v2(rows[1:], path)
    if rows and rows[0][1][0] == "Image ID":
        return _read_v1(rows, path)
    raise InputError(f"{path}, line 1: not a MorphoMetriX CSV (expected the header "
                     f"{','.join(V2_HEADER)} of v2 or the 'Image ID' row of v1)")


def number_text(value: float) -> str:
    """A number as CSV text, 10 significant digits (no float noise like 2.500000000000001)."""
    return format(float(value), ".10g")


def _write_rows(path: Path, rows: list[list[str]]) -> None:
    """Write CSV rows atomically with CRLF line ends, as MorphoMetriX does."""
    with atomic_path(Path(path)) as tmp, tmp.open("w", newline="", encoding="utf-8") as file:
        csv.writer(file, lineterminator="\r\n").writerows(rows)


def write_morphometrix_v1(path: Path, record: MorphoMetrixRecord) -> None:
    """Write ``record`` as a MorphoMetriX v1 block CSV (atomically), laid out as MorphoMetriX
    v1's own ``demo-annotated.csv``: metadata rows; ``Object,Length (m),5.00% Width,…`` with
    a row per length in metres; ``Object,Angle`` and ``Object,Area (m²)`` blocks where there
    are any. Every row has as many cells. Pixels and the mirror side are left out: v1 has
    neither (mirror-side widths are written doubled, as the record holds them).
    """
    meta = [record.image_id, record.image_path, number_text(record.focal_mm),
            number_text(record.altitude_m), number_text(record.pixel_dimension_mm),
            record.notes]
    percents = sorted({pct for widths in record.widths_m.values() for pct in widths})
    rows = [[name, value] for name, value in zip(V1_METADATA, meta)]
    rows += [[], V1_LENGTH_HEAD + [f"{pct:.2f}% Width" for pct in percents]]
    for name, value in record.lengths_m.items():
        widths = record.widths_m.get(name, {})
        rows.append([name, number_text(value)] + [number_text(widths[pct]) if pct in widths
                                                  else "" for pct in percents])
    for unit, head in V1_OTHER_HEADS.items():
        block = [[name, number_text(value)] for name, value, other_unit in record.others
                 if other_unit == unit]
        rows += [[], head, *block] if block else []
    num_columns = max(map(len, rows))
    _write_rows(path, [row + [""] * (num_columns - len(row)) for row in rows])


def write_morphometrix_v2(path: Path, record: MorphoMetrixRecord) -> None:
    """Write ``record`` as a MorphoMetriX v2 long CSV (atomically).

    As MorphoMetriX does, the metre section comes first and angles appear in both sections;
    areas are in square metres, then in (square) pixels under the unit ``Pixels``.
    """
    meta = {"Image ID": record.image_id, "Image Path": record.image_path,
            "Focal Length": number_text(record.focal_mm),
            "Altitude": number_text(record.altitude_m),
            "Pixel Dimension": number_text(record.pixel_dimension_mm),
            "Mirror Side": record.mirror_side or "None", "Notes": record.notes}
    rows = [V2_HEADER] + [[name, value, METADATA] for name, value in meta.items()]
    sections = ((METERS, record.lengths_m, record.widths_m, SQUARE_METERS),
                (PIXELS, record.lengths_px, record.widths_px, SQUARE_PIXELS))
    for unit, lengths, widths, area_unit in sections:
        for name, value in lengths.items():
            rows.append([name, number_text(value), unit])
            rows += [[width_name(name, pct), number_text(w), unit]
                     for pct, w in sorted(widths.get(name, {}).items())]
        rows += [[name, number_text(value), other_unit if other_unit != SQUARE_PIXELS
                  else PIXELS] for name, value, other_unit in record.others
                 if other_unit in (DEGREES, area_unit)]
    _write_rows(path, rows)


WRITERS = {1: write_morphometrix_v1, 2: write_morphometrix_v2}  # by MorphoMetriX version


def write_morphometrix(path: Path, record: MorphoMetrixRecord, version: int = 2) -> None:
    """Write ``record`` as a MorphoMetriX CSV of ``version`` (MMX_VERSIONS)."""
    WRITERS[version](path, record)


def record_from_pixels(pixels: PixelMeasurements, *, image_id: str, image_path: str,
                       focal_mm: float, pixel_dimension_mm: float, altitude_m: float,
                       mirror_side: str | None, notes: str = "",
                       length_name: str = LENGTH_NAME) -> MorphoMetrixRecord:
    """A v2 record of a length and its measured station widths, in metres and pixels.

    Unmeasured (NaN) stations are left out, as MorphoMetriX has no "skipped" value.
    """
    record = MorphoMetrixRecord(
        version=2, image_id=image_id, image_path=image_path, focal_mm=focal_mm,
        altitude_m=altitude_m, pixel_dimension_mm=pixel_dimension_mm,
        mirror_side=mirror_side, notes=notes)
    is_measured = np.isfinite(pixels.widths_px)
    widths_px = dict(zip(STATION_PCT[is_measured].tolist(),
                         pixels.widths_px[is_measured].tolist()))
    return replace(
        record,
        lengths_px={length_name: pixels.length_px},
        lengths_m={length_name: pixels.length_px * record.m_per_px},
        widths_px={length_name: widths_px},
        widths_m={length_name: {pct: w * record.m_per_px for pct, w in widths_px.items()}},
    )


def pixel_measurements(record: MorphoMetrixRecord, path: Path,
                       length_name: str | None = None) -> PixelMeasurements:
    """Length and the 19 station widths in pixels (from metres where a file has no pixels).

    ``length_name``: the total length's name (default: any of TOTAL_LENGTH_NAMES; see
    :func:`total_length_name`). Stations missing from the file are NaN; widths off the 5 %
    grid, an implausible body length and widths not between zero and the length are refused
    (core.limits).
    """
    length_name = total_length_name(record, path, length_name)
    from_m = length_name not in record.lengths_px
    lengths = record.lengths_m if from_m else record.lengths_px
    scale = 1.0 / record.m_per_px if from_m else 1.0
    widths = (record.widths_m if from_m else record.widths_px).get(length_name, {})
    widths_px = np.full(len(STATION_PCT), np.nan)
    for pct, width in widths.items():
        matches = np.flatnonzero(np.isclose(STATION_PCT, pct))
        if len(matches) != 1:
            raise InputError(f"{path}: width {width_name(length_name, pct)} is not on the "
                             f"5 % stations the elliptical method uses")
        widths_px[matches[0]] = width * scale
    m_per_px = record.m_per_px
    body_measurements(lengths[length_name] * scale * m_per_px, (widths_px * m_per_px).tolist(),
                      f"{path}: {length_name}")
    return PixelMeasurements(length_px=lengths[length_name] * scale, widths_px=widths_px,
                             is_mirrored=record.mirror_side is not None)
