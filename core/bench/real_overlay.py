"""Pictures of ``dolphinfit bench real``: our mask, suggested midline and width edges over a
real image, beside what people clicked, for a person to judge."""

from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.measure.annotation import Annotation, place_stations

WIDTH_PX = 1600      # the picture's width
MASK_BGR = (255, 0, 255)
MIDLINE_BGR = (0, 255, 255)
EDGES_BGR = (0, 255, 0)
PEOPLE_BGR = (255, 255, 0)
CLICK_BGR = (0, 0, 255)


def overlay(rgb: np.ndarray, mask: np.ndarray, annotation: Annotation,
            people_px: np.ndarray | None = None,
            click_px: tuple[float, float] | None = None) -> np.ndarray:
    """(h, WIDTH_PX, 3) BGR picture: the mask's outline (magenta), the suggested midline
    (yellow) and width edges (green), people's points (N, 2) (cyan) and the seed's click
    (red), over the image scaled to ``WIDTH_PX`` wide."""
    scale = WIDTH_PX / rgb.shape[1]
    size = (WIDTH_PX, round(rgb.shape[0] * scale))
    picture = cv2.resize(cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR), size,
                         interpolation=cv2.INTER_AREA)
    outline = cv2.resize(mask.astype(np.uint8), size, interpolation=cv2.INTER_NEAREST)
    contours, _ = cv2.findContours(outline, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    cv2.drawContours(picture, contours, -1, MASK_BGR, 1, cv2.LINE_AA)

    def at(points: np.ndarray) -> np.ndarray:
        return np.round((np.asarray(points) + 0.5) * scale - 0.5).astype(np.int32)

    stations = place_stations(annotation.midline_px, np.linspace(0.0, 1.0, 101))
    cv2.polylines(picture, [at(stations.points_px)], False, MIDLINE_BGR, 1, cv2.LINE_AA)
    for side_a, side_b in annotation.edges_px:
        if np.isfinite(side_a).all() and np.isfinite(side_b).all():
            cv2.line(picture, *map(tuple, at([side_a, side_b])), EDGES_BGR, 1, cv2.LINE_AA)
    for point in ([] if people_px is None else at(people_px)):
        cv2.circle(picture, tuple(point), 3, PEOPLE_BGR, -1, cv2.LINE_AA)
    if click_px is not None:
        cv2.drawMarker(picture, tuple(at(click_px)), CLICK_BGR, cv2.MARKER_CROSS, 12, 2)
    return picture


def write_overlay(path: Path, picture: np.ndarray) -> None:
    """Write a picture to a .png path, atomically."""
    with atomic_path(path) as temporary:
        if not cv2.imwrite(str(temporary), picture):
            raise OSError(f"{path}: could not be written as an image")
