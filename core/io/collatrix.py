"""CollatriX / Xcertainty wide CSV: one row per measured image, one column per value.

Column names follow reference/ecosystem.md §6.2: CollatriX's metadata columns (``Image``,
``Image_ID``, ``Image_Path``, ``Altitude``, ``Focal_Length``, ``Pixel_Dimension``,
``Mirror_Side``, ``Notes``), Xcertainty's calibration inputs (``Baro_Alt``, ``Laser_Alt``,
``Launch_Ht``, ``Iw`` image width in px, ``Sw`` sensor width in mm, ``uas``), then every
length and width with ``_m`` and ``_px`` suffixes (``TL_m``, ``TL_px``, ``TL_w05.00_px``, …),
angles with ``_deg``, areas with ``_m2`` / ``_px2``, and any extra result columns the caller
adds (HW ratios as ``TL_ratio5.00``, volumes, BCI, mass). The altitude goes to ``Laser_Alt``
or ``Baro_Alt`` by its source; ``Baro_Alt`` already includes the launch height, so
``Launch_Ht`` stays empty. Empty cells mean "not available".
"""

import csv
from collections.abc import Mapping, Sequence
from pathlib import Path

from core.io.atomic import atomic_path
from core.io.morphometrix import (
    DEGREES, SQUARE_METERS, SQUARE_PIXELS, MorphoMetrixRecord, number_text, width_name,
)

ALTITUDE_COLUMN_BY_SOURCE = {"laser": "Laser_Alt", "barometer": "Baro_Alt"}  # Xcertainty
OTHER_SUFFIX = {DEGREES: "deg", SQUARE_METERS: "m2", SQUARE_PIXELS: "px2"}


def _cell(value: object) -> str:
    """A value as CSV text; None → empty; floats with 10 significant digits."""
    if value is None:
        return ""
    return number_text(value) if isinstance(value, float) else str(value)


def wide_row(record: MorphoMetrixRecord, *, image: str, altitude_source: str | None = None,
             image_width_px: int | None = None, sensor_width_mm: float | None = None,
             uas: str = "", extras: Mapping[str, object] | None = None) -> dict[str, str]:
    """The wide-format row of one image's measurements.

    image: the ``Image`` column (e.g. the measurement file's name); altitude_source: laser,
    barometer or manual (None: unknown); image_width_px and sensor_width_mm: Xcertainty's
    ``Iw`` and ``Sw``; extras: further columns, in order.
    """
    row: dict[str, object] = {
        "Image": image, "Image_ID": record.image_id, "Image_Path": record.image_path,
        "Altitude": record.altitude_m, "Altitude_Source": altitude_source,
        "Baro_Alt": None, "Laser_Alt": None, "Launch_Ht": None,
        "Focal_Length": record.focal_mm, "Pixel_Dimension": record.pixel_dimension_mm,
        "Iw": image_width_px, "Sw": sensor_width_mm, "uas": uas,
        "Mirror_Side": record.mirror_side or "None", "Notes": record.notes,
    }
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
