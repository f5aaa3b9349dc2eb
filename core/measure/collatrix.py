"""CollatriX and Xcertainty tables: one row per measured image, one column per value.

Two tables, both keyed like CollatriX's (``Image``: the image file's base name, as CollatriX
takes it from MorphoMetriX's ``Image Path``; ``Image_ID``; ``csv``: the MorphoMetriX file):

- **CollatriX table** (:func:`collatrix_row`): what CollatriX v2's body-condition tool reads as
  it is (MMI-CODEX/CollatriX ``collatrix/__main__.py``; reference/ecosystem.md §2). Metres
  only, under the leading columns of CollatriX's own collated table (``csv, Image, Image_ID,
  Image_Path, Altitude, Focal_Length, Pixel_Dimension, Mirror_Side, Notes,
  metadata_source``); each length under its bare name (``TL``); widths as ``TL_w5.00`` …
  ``TL_w95.00`` (it builds the names as the percent with two decimals, unpadded, so its own
  collated ``TL_w05.00`` is not found); HW ratios as ``TL_ratio5.00`` … ``TL_ratio85.00``, the
  ones its elliptical volume reads. It picks width columns by substring, so no other column
  may contain a width name (no ``_px`` twins, no ``BVell_5perc`` of ours that its merge
  would rename). A missing width fails it and an empty one silently drops two segments from
  its volume, so the caller gives every station (``Filled_Widths`` lists those interpolated).
- **Wide table** (:func:`wide_row`): ours, richer, for Xcertainty and for reading (column names
  of reference/ecosystem.md §6.2): the metadata columns, Xcertainty's calibration inputs
  (``Altitude_Source``, ``Baro_Alt``, ``Laser_Alt``, ``Launch_Ht``, ``Iw`` image width in px,
  ``Sw`` sensor width in mm, ``uas``), then every length and measured width with ``_m`` and
  ``_px`` suffixes (``TL_m``, ``TL_px``, ``TL_w05.00_px``, …), angles with ``_deg``, areas
  with ``_m2`` / ``_px2``, and the result columns the caller adds (HW ratios, volumes, BCI,
  mass). The altitude goes to ``Laser_Alt`` or ``Baro_Alt`` by its source; ``Baro_Alt``
  already includes the launch height, so ``Launch_Ht`` stays empty.

Empty cells mean "not available".
"""

import csv
from collections.abc import Mapping, Sequence
from pathlib import Path, PureWindowsPath

from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.measure.morphometrix import (
    DEGREES, LENGTH_NAME, SQUARE_METERS, SQUARE_PIXELS, MorphoMetrixRecord, number_text,
    width_name,
)

ALTITUDE_COLUMN_BY_SOURCE = {"laser": "Laser_Alt", "barometer": "Baro_Alt"}  # Xcertainty
OTHER_SUFFIX = {DEGREES: "deg", SQUARE_METERS: "m2", SQUARE_PIXELS: "px2"}
COLLATRIX_METADATA_SOURCE = "mmx_input"  # CollatriX's value when metres come with the file
COLLATRIX_RATIO_PCT = tuple(range(5, 90, 5))  # the HW ratios its elliptical volume reads


def _cell(value: object) -> str:
    """A value as CSV text; None → empty; floats with 10 significant digits."""
    if value is None:
        return ""
    return number_text(value) if isinstance(value, float) else str(value)


def _image_name(record: MorphoMetrixRecord, csv_name: str) -> str:
    """CollatriX's ``Image``: the base name of the record's image path (Windows or POSIX
    separators), else ``csv_name``."""
    return PureWindowsPath(record.image_path).name or csv_name


def _metadata(record: MorphoMetrixRecord, csv_name: str) -> dict[str, object]:
    """The leading columns both tables share, CollatriX's names and order."""
    return {"csv": csv_name, "Image": _image_name(record, csv_name),
            "Image_ID": record.image_id, "Image_Path": record.image_path,
            "Altitude": record.altitude_m, "Focal_Length": record.focal_mm,
            "Pixel_Dimension": record.pixel_dimension_mm,
            "Mirror_Side": record.mirror_side or "None", "Notes": record.notes}


def collatrix_width_name(length_name: str, pct: float) -> str:
    """The width name CollatriX's body-condition tool looks for, e.g. ``TL_w5.00``."""
    return f"{length_name}_w{pct:.2f}"


def collatrix_row(record: MorphoMetrixRecord, *, csv_name: str,
                  hw_ratios: Mapping[float, float],
                  filled_pct: Sequence[float] = ()) -> dict[str, str]:
    """The CollatriX-table row of one image (module docstring).

    record: metres of the lengths, widths (every station of ``TL``, filled ones included),
    angles and areas; csv_name: the MorphoMetriX file written beside it (``csv``, and
    ``Image`` without an image path); hw_ratios: HW ratio by percent, at least at
    COLLATRIX_RATIO_PCT; filled_pct: the widths interpolated, not measured.
    """
    row = {**_metadata(record, csv_name), "metadata_source": COLLATRIX_METADATA_SOURCE}
    for name, value in record.lengths_m.items():
        row[name] = value
        row.update({collatrix_width_name(name, pct): w
                    for pct, w in sorted(record.widths_m.get(name, {}).items())})
    row.update({name: value for name, value, unit in record.others if unit != SQUARE_PIXELS})
    row.update({f"{LENGTH_NAME}_ratio{pct:.2f}": hw_ratios[pct] for pct in COLLATRIX_RATIO_PCT})
    row["Filled_Widths"] = " ".join(f"{pct:g}" for pct in filled_pct)
    return {key: _cell(value) for key, value in row.items()}


def wide_row(record: MorphoMetrixRecord, *, csv_name: str, altitude_source: str | None = None,
             image_width_px: int | None = None, sensor_width_mm: float | None = None,
             uas: str = "", extras: Mapping[str, object] | None = None) -> dict[str, str]:
    """The wide-table row of one image's measurements (module docstring).

    csv_name: the MorphoMetriX file written beside it; altitude_source: laser, barometer or
    manual (None: unknown); image_width_px and sensor_width_mm: Xcertainty's ``Iw`` and
    ``Sw``; extras: further columns, in order.
    """
    row = _metadata(record, csv_name)
    row.update({"Altitude_Source": altitude_source, "Baro_Alt": None, "Laser_Alt": None,
                "Launch_Ht": None, "Iw": image_width_px, "Sw": sensor_width_mm, "uas": uas})
    if altitude_source in ALTITUDE_COLUMN_BY_SOURCE:
        row[ALTITUDE_COLUMN_BY_SOURCE[altitude_source]] = record.altitude_m
    for suffix, lengths, widths in (("m", record.lengths_m, record.widths_m),
                                    ("px", record.lengths_px, record.widths_px)):
        for name, value in lengths.items():
            row[f"{name}_{suffix}"] = value
            row.update({f"{width_name(name, pct)}_{suffix}": w
                        for pct, w in sorted(widths.get(name, {}).items())})
    row.update({f"{name}_{OTHER_SUFFIX[unit]}": value for name, value, unit in record.others})
    row.update(extras or {})
    return {key: _cell(value) for key, value in row.items()}


def write_wide_csv(path: Path, rows: Sequence[Mapping[str, str]]) -> None:
    """Write rows (atomically) under the union of their columns, in first-seen order."""
    columns = list(dict.fromkeys(key for row in rows for key in row))
    with atomic_path(Path(path)) as tmp, tmp.open("w", newline="", encoding="utf-8") as file:
        writer = csv.DictWriter(file, fieldnames=columns, restval="")
        writer.writeheader()
        writer.writerows(rows)
