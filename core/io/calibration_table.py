"""Tables of a calibration object measured in pixels at recorded altitudes.

Three layouts are read, each as the tool that writes it names its columns (one row per image):

- **ours**: ``image``, ``altitude_m``, ``pixel_length`` and optionally ``object_length_m``,
  ``focal_mm``, ``sensor_width_mm``, ``image_width_px``, ``drone``, ``resolution``;
- **MedidoR**'s calibration sheet (``calib.xlsx``): ``Pixel`` or ``OBJ_P``, ``C_Alt`` (flight
  plus take-off altitude), ``ObjLength`` or ``OBJ_L`` in **centimetres**, ``Drone``,
  ``Resolution`` (the video mode, e.g. "2.7k") and, in newer sheets, ``flen``, ``sw``, ``iw``;
- **Xcertainty**'s training tables (``calibration``, ``co_data``: ``Lpix``, ``CO.L`` in metres,
  ``Baro_Alt``, ``Laser_Alt``, ``Focal_Length``, ``Sw``, ``Iw``, ``uas``; the older
  ``calibration2``: ``RRR.pix``, ``L_train``, ``Baro...Ht``, ``Focal.length``, ``Aircraft``).

As CSV, .xlsx (its first sheet) or an R data file (.rda/.RData with one data frame), read with
pandas and rdata. A table with both a barometer and a laser column needs the altimeter named.
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError

ALTIMETERS = ("barometer", "laser")
# role → the column names that hold it, in the order they are looked for
COLUMNS: dict[str, tuple[str, ...]] = {
    "image": ("image", "Image", "Images", "ID", "imid"),
    "pixel_length": ("pixel_length", "Pixel", "OBJ_P", "Lpix", "RRR.pix"),
    "object_length_m": ("object_length_m", "CO.L", "L_train"),
    "object_length_cm": ("ObjLength", "OBJ_L"),
    "focal_mm": ("focal_mm", "flen", "Focal_Length", "Focal.length"),
    "sensor_width_mm": ("sensor_width_mm", "sw", "Sw"),
    "image_width_px": ("image_width_px", "iw", "Iw"),
    "drone": ("drone", "Drone", "uas", "Aircraft"),
    "resolution": ("resolution", "Resolution"),
}
ALTITUDE_COLUMNS: dict[str, tuple[str, ...]] = {
    "barometer": ("C_Alt", "Baro_Alt", "Baro...Ht"),
    "laser": ("Laser_Alt",),
}
OWN_ALTITUDE = "altitude_m"
CM_PER_M = 100.0
SAME_VALUE_RTOL = 1e-6   # rows that differ by less state one value


@dataclass(frozen=True)
class CalibrationShot:
    """One image of the calibration object: what the altimeter said and what was measured.

    Camera fields and the object's length are NaN where the table does not carry them."""

    image: str
    recorded_altitude_m: float
    pixel_length: float
    object_length_m: float
    focal_mm: float
    sensor_width_mm: float
    image_width_px: float
    drone: str


@dataclass(frozen=True)
class CalibrationTable:
    """The shots of one drone and altimeter, and where they came from.

    ``resolution``: the video mode the shots' rows name (e.g. "2.7k"); "" when they name
    none or several."""

    path: Path
    altimeter_column: str
    drone: str
    shots: tuple[CalibrationShot, ...]
    resolution: str = ""

    def known_values(self, name: str) -> np.ndarray:
        """(N,) the values of shot field ``name`` that the shots carry (NaN ones left out)."""
        values = np.array([getattr(shot, name) for shot in self.shots], dtype=float)
        return values[np.isfinite(values)]

    def common_value(self, name: str, what: str | None = None) -> float | None:
        """The value of shot field ``name`` all the shots that carry it share; None when none
        does. InputError naming the file (and ``what``, else ``name``) when they disagree."""
        known = self.known_values(name)
        if not known.size:
            return None
        if not np.allclose(known, known[0], rtol=SAME_VALUE_RTOL, atol=0.0):
            listed = ", ".join(f"{value:g}" for value in np.unique(known))
            raise InputError(f"{self.path}: the rows disagree on {what or name} ({listed}): "
                             f"one calibration holds for one object and camera; split the table")
        return float(known[0])


def _frame(path: Path):
    """The table as a pandas DataFrame; InputError if it cannot be read."""
    import pandas as pd  # only the readers of tables pay for it

    suffix = path.suffix.lower()
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    try:
        if suffix == ".csv":
            return pd.read_csv(path)
        if suffix == ".xlsx":
            return pd.read_excel(path, sheet_name=0, engine="openpyxl")
        if suffix in (".rda", ".rdata"):
            import rdata

            frames = [value for value in rdata.read_rda(path).values()
                      if isinstance(value, pd.DataFrame)]
            if len(frames) != 1:
                raise InputError(f"{path}: expected one data frame in the R data file, found "
                                 f"{len(frames)}")
            return frames[0]
    except InputError:
        raise
    except Exception as exc:  # pandas, openpyxl and rdata raise many kinds
        raise InputError(f"{path}: cannot be read as a {suffix} table ({exc})") from None
    raise InputError(f"{path}: a calibration table must be .csv, .xlsx or .rda, "
                     f"not {suffix or 'a file without an extension'}")


def _column(frame, names: tuple[str, ...]) -> str | None:
    return next((name for name in names if name in frame.columns), None)


def _altitude_column(path: Path, frame, altimeter: str | None) -> str:
    """The column of recorded altitudes: ours, or the named altimeter's (the only one with
    values when the table has one)."""
    if OWN_ALTITUDE in frame.columns:
        return OWN_ALTITUDE
    found = {kind: column for kind, names in ALTITUDE_COLUMNS.items()
             if (column := _column(frame, names)) is not None
             and (frame[column].fillna(0) > 0).any()}
    if altimeter is not None:
        if altimeter not in found:
            raise InputError(f"{path}: no {altimeter} altitudes (columns "
                             f"{', '.join(ALTITUDE_COLUMNS[altimeter])}) with values")
        return found[altimeter]
    if not found:
        raise InputError(f"{path}: no altitude column ({OWN_ALTITUDE}, "
                         f"{', '.join(sum(ALTITUDE_COLUMNS.values(), ()))})")
    if len(found) > 1:
        raise InputError(f"{path}: both barometer ({found['barometer']}) and laser "
                         f"({found['laser']}) altitudes; say which with --altimeter")
    return next(iter(found.values()))


def _numbers(path: Path, frame, column: str | None, scale: float = 1.0) -> np.ndarray:
    """The column as floats (NaN where absent); InputError naming the row of a non-number."""
    if column is None:
        return np.full(len(frame), np.nan)
    values = []
    for row_no, value in enumerate(frame[column], start=2):
        try:
            values.append(float(value) / scale)
        except (TypeError, ValueError):
            raise InputError(f"{path}, row {row_no}: {column} {value!r} is not a number") \
                from None
    return np.array(values)


def read_calibration_table(path: Path | str, altimeter: str | None = None,
                           drone: str | None = None) -> CalibrationTable:
    """The shots of ``drone`` (the only one when the table has one) with ``altimeter``'s
    altitudes, in file order. Rows without a pixel length or an altitude (0 or blank, as
    MedidoR and Xcertainty write a missing reading) are left out; InputError naming the file
    when none is left, a required column is missing or a drone must be chosen."""
    path = Path(path)
    frame = _frame(path)
    pixel_column = _column(frame, COLUMNS["pixel_length"])
    if pixel_column is None:
        raise InputError(f"{path}: no pixel-length column "
                         f"({', '.join(COLUMNS['pixel_length'])})")
    altitude_column = _altitude_column(path, frame, altimeter)
    drone_column = _column(frame, COLUMNS["drone"])
    drones = [] if drone_column is None else sorted({str(d) for d in frame[drone_column]})
    if drone is not None and drone not in drones:
        raise InputError(f"{path}: no drone {drone!r}; the table has "
                         f"{', '.join(drones) or 'no drone column'}")
    if drone is None and len(drones) > 1:
        raise InputError(f"{path}: shots of {len(drones)} drones ({', '.join(drones)}); a "
                         f"calibration is one drone's: choose one with --drone, or import a "
                         f"table of that drone's rows")
    chosen = drone if drone is not None else (drones[0] if drones else "")
    frame = frame.assign(_row=np.arange(len(frame)) + 2)   # the spreadsheet's row numbers
    if drone_column is not None:
        frame = frame[frame[drone_column].astype(str) == chosen]
    length_m = _numbers(path, frame, _column(frame, COLUMNS["object_length_m"]))
    length_cm = _column(frame, COLUMNS["object_length_cm"])
    if length_cm is not None:
        length_m = _numbers(path, frame, length_cm, scale=CM_PER_M)
    image_column = _column(frame, COLUMNS["image"])
    resolution_column = _column(frame, COLUMNS["resolution"])
    resolutions = ({str(value).strip() for value in frame[resolution_column].dropna()}
                   if resolution_column is not None else set())
    columns = {role: _numbers(path, frame, _column(frame, COLUMNS[role]))
               for role in ("focal_mm", "sensor_width_mm", "image_width_px")}
    pixels = _numbers(path, frame, pixel_column)
    altitudes = _numbers(path, frame, altitude_column)
    shots = tuple(
        CalibrationShot(
            image=(str(frame[image_column].iloc[i]) if image_column
                   else f"row {frame['_row'].iloc[i]}"),
            recorded_altitude_m=float(altitudes[i]), pixel_length=float(pixels[i]),
            object_length_m=float(length_m[i]), focal_mm=float(columns["focal_mm"][i]),
            sensor_width_mm=float(columns["sensor_width_mm"][i]),
            image_width_px=float(columns["image_width_px"][i]), drone=chosen)
        for i in range(len(frame))
        if pixels[i] > 0 and altitudes[i] > 0)
    if not shots:
        raise InputError(f"{path}: no row with both a pixel length ({pixel_column}) and an "
                         f"altitude ({altitude_column})")
    return CalibrationTable(path=path, altimeter_column=altitude_column, drone=chosen,
                            shots=shots,
                            resolution=resolutions.pop() if len(resolutions) == 1 else "")
