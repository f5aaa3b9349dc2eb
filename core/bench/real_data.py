"""The real drone images and measurements made by people that ``dolphinfit bench real`` scores
the product against (shipped in a clone's ``tests/data/real/``; ``SOURCES.md`` there gives
each file's repository, commit and licence):

- **minke**: a minke whale from a drone (MorphoMetriX's demo image, 2978×1985 px, 35 mm lens,
  28.4 m) measured by hand twice, by two people: 19 widths (5–95 %) and 9 widths (10–90 %);
- **medidor**: a southern right whale with its calf (DJI Mavic Air 2, 2.7K, 23 m), with the
  clicks of MedidoR's own GUI test (read from its R test file) and the spreadsheet MedidoR
  writes from them;
- **outlines**: 639 southern right whale outlines with 19 points placed by hand on each
  (Bagchi et al. 2025; the images are not public), converted from the repository's pickle to
  an .npz of integers, equal point for point.
"""

import csv
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.medidor import MedidorRow, read_medidor
from dolphinfit.core.measure.morphometrix import (
    MorphoMetrixRecord, read_morphometrix, total_length_name,
)
from dolphinfit.core.measure.annotation import Calibration
from dolphinfit.core.measure.stations import STATION_PCT

REAL_DATA_DIR = Path(__file__).resolve().parents[2] / "tests" / "data" / "real"
MINKE_HUMANS = ("demo-annotated.csv", "test-image.csv")
# Where a user clicks the animal to track it: on the back, between the flippers (pixels)
MINKE_CLICK_PX = (1200.0, 1040.0)
MEDIDOR_CLICK_PX = (1300.0, 860.0)
CLICK = re.compile(r"list\(x = (?P<x>-?[\d.]+), y = (?P<y>-?[\d.]+)\)")
# The hand points of the outline set: pairs across the body, rostrum to peduncle
OUTLINE_PAIRS = ("head1", "head2", "eye", "body1", "body2", "body3", "peduncle_width")
OFF_OUTLINE_SHARE = 0.03  # a rostrum or peduncle point further off the outline (× length)


def real_data_dir(folder: Path | None = None) -> Path:
    """The folder of the real data sets: ``folder``, else the clone's tests/data/real.

    InputError when it does not hold them (an installed package has no tests/ folder)."""
    path = REAL_DATA_DIR if folder is None else Path(folder)
    if not (path / "minke").is_dir():
        raise InputError(f"{path}: no real data sets here (they ship in a clone of dolphinfit "
                         f"under tests/data/real/; name that folder with --data)")
    return path


@dataclass(frozen=True)
class HumanMeasurement:
    """One person's measurement of an image, as their tool saved it."""

    source: str                    # file name
    length_m: float
    widths_m: dict[float, float]   # percent of body length → width, m

    def station_widths(self) -> np.ndarray:
        """(19,) the widths on the station grid, NaN where not measured."""
        return np.array([self.widths_m.get(float(pct), np.nan) for pct in STATION_PCT])


@dataclass(frozen=True)
class MinkeImage:
    """The minke whale image, its camera and altitude, and both people's measurements."""

    image: Path
    calibration: Calibration
    humans: tuple[HumanMeasurement, ...]
    click_px: tuple[float, float]


@dataclass(frozen=True)
class MedidorImage:
    """The right whale image, MedidoR's test clicks and the spreadsheet they produce.

    ``length_clicks_px``: (3, 2) rostrum, mid-point, fluke notch; ``width_clicks_px``:
    (9, 2, 2) both sides at 10 … 90 %; ``fluke_clicks_px``: (2, 2) the fluke tips.
    """

    image: Path
    calibration: Calibration
    length_clicks_px: np.ndarray
    width_clicks_px: np.ndarray
    fluke_clicks_px: np.ndarray
    sheet: MedidorRow
    click_px: tuple[float, float]


@dataclass(frozen=True)
class WhaleOutlines:
    """Outlines (N, 2, P) (x, y) of whale bodies (rostrum to peduncle, no flukes or flippers)
    and the hand points on each: ``points[name]`` (N, 2). ``left_out``: (index, why) of
    outlines not usable (points outside their image)."""

    outlines: np.ndarray
    points: dict[str, np.ndarray]
    left_out: tuple[tuple[int, str], ...]


def _camera(name: str, focal_mm: float, sensor_width_mm: float, width_px: int,
            height_px: int, source: str) -> CameraPreset:
    return CameraPreset(name=name, description=source, focal_mm=focal_mm,
                        sensor_width_mm=sensor_width_mm, image_width_px=width_px,
                        image_height_px=height_px, source=source, approximate=False)


def _image_size(path: Path) -> tuple[int, int]:
    import cv2

    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise InputError(f"{path}: cannot be read as an image")
    return image.shape[1], image.shape[0]


def _human(path: Path, record: MorphoMetrixRecord) -> HumanMeasurement:
    name = total_length_name(record, path)
    return HumanMeasurement(path.name, record.lengths_m[name],
                            dict(record.widths_m.get(name, {})))


def load_minke(folder: Path | None = None) -> MinkeImage:
    """The minke image with its two human measurements."""
    root = real_data_dir(folder) / "minke"
    records = [(root / name, read_morphometrix(root / name)) for name in MINKE_HUMANS]
    first = records[0][1]
    image = root / "demo.JPG"
    width, height = _image_size(image)
    camera = _camera("minke", first.focal_mm, first.pixel_dimension_mm * width, width, height,
                     "MorphoMetriX demo: focal length and pixel dimension of its CSV")
    return MinkeImage(image, Calibration(camera, None, first.altitude_m, "manual"),
                      tuple(_human(path, record) for path, record in records), MINKE_CLICK_PX)


def medidor_clicks(path: Path) -> np.ndarray:
    """(N, 2) every ``list(x = …, y = …)`` click of MedidoR's GUI test, in file order."""
    from dolphinfit.core.io.text_input import read_text

    return np.array([[float(m["x"]), float(m["y"])] for m in CLICK.finditer(read_text(path))])


def load_medidor(folder: Path | None = None) -> MedidorImage:
    """The right whale image with MedidoR's test clicks and its spreadsheet."""
    root = real_data_dir(folder) / "medidor"
    clicks = medidor_clicks(root / "test-app-MedidoR.R")
    if len(clicks) != 3 + 18 + 2:
        raise InputError(f"{root / 'test-app-MedidoR.R'}: expected 23 clicks (length, 9 width "
                         f"pairs, fluke tips), found {len(clicks)}")
    sheet = read_medidor(root / "Measurements_10.xlsx")[0]
    image = root / "example_whale.png"
    width, height = _image_size(image)
    camera = _camera("medidor", sheet.focal_mm, sheet.sensor_width_mm, width, height,
                     "as MedidoR's GUI test enters it")
    return MedidorImage(image, Calibration(camera, None, sheet.altitude_m, "barometer"),
                        clicks[:3], clicks[3:21].reshape(9, 2, 2), clicks[21:], sheet,
                        MEDIDOR_CLICK_PX)


def load_outlines(folder: Path | None = None) -> WhaleOutlines:
    """The 639 whale outlines and their hand points."""
    root = real_data_dir(folder) / "save-the-whales"
    outlines = np.load(root / "outlines.npz")["outlines"].astype(np.float64)
    with (root / "hand_points.csv").open(newline="", encoding="utf-8") as file:
        rows = list(csv.DictReader(file))
    if len(rows) != len(outlines):
        raise InputError(f"{root}: {len(outlines)} outlines but {len(rows)} rows of points")
    names = ["rostrum", "peduncle", "fluke", "len_mid"] + [
        f"{side}_{pair}" for pair in OUTLINE_PAIRS for side in ("side1", "side2")]
    points = {name: np.array([[float(r[f"{name}_x"]), float(r[f"{name}_y"])] for r in rows])
              for name in names}
    size = np.array([[float(r["Image.Width"]), float(r["Image.Length"])] for r in rows])
    left_out = tuple((i, why) for i in range(len(outlines))
                     if (why := _unusable(outlines[i], size[i], points["rostrum"][i],
                                          points["peduncle"][i])))
    return WhaleOutlines(outlines, points, left_out)


def _unusable(outline: np.ndarray, image_size: np.ndarray, rostrum: np.ndarray,
              peduncle: np.ndarray) -> str:
    """Why an outline (2, P) cannot be scored against its hand points; "" if it can."""
    if outline.min() < 0 or np.any(outline.max(axis=1) > image_size):
        return "outline points outside the image"
    if crossings(outline):
        return "the outline crosses itself"
    length = np.linalg.norm(rostrum - peduncle)
    for name, point in (("rostrum", rostrum), ("peduncle", peduncle)):
        if distance_to_outline(point, outline) > OFF_OUTLINE_SHARE * length:
            return f"the {name} point lies off the outline"
    return ""


def _segments(outline: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(P, 2) start and end points of a closed outline's segments."""
    start = outline.T
    return start, np.roll(start, -1, axis=0)


def crossings(outline: np.ndarray) -> int:
    """How many pairs of non-adjacent segments of a closed outline (2, P) cross."""
    start, end = _segments(outline)

    def turn(p, q, r):   # the sign of the turn p → q → r
        return np.sign((q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1])
                       - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0]))

    a, b, c, d = start[:, None], end[:, None], start[None], end[None]
    cross = (turn(a, b, c) * turn(a, b, d) < 0) & (turn(c, d, a) * turn(c, d, b) < 0)
    first, second = np.nonzero(np.triu(cross, 2))
    return int(np.sum(~((first == 0) & (second == len(start) - 1))))


def distance_to_outline(point: np.ndarray, outline: np.ndarray) -> float:
    """The distance (px) from a point (2,) to a closed outline (2, P)."""
    start, end = _segments(outline)
    along = end - start
    share = np.clip(np.sum((point - start) * along, axis=1)
                    / np.maximum(np.sum(along * along, axis=1), 1e-12), 0.0, 1.0)
    return float(np.min(np.linalg.norm(start + share[:, None] * along - point, axis=1)))
