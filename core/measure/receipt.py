"""The PNG "image receipt" of a measured frame (MorphoMetriX's name for it): the frame with the
midline, the station perpendiculars, the measured widths and a caption with the results.

Line widths and text scale with the frame so that the drawing reads on 4K frames and on small
stills alike. Hershey fonts are ASCII only, hence "m^3".
"""

from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.measure.annotation import (
    SIDES, Annotation, edge_offsets, midline_spline, place_stations,
)

# Colours (RGB)
MIDLINE_RGB = (255, 215, 0)
GUIDE_RGB = (200, 200, 200)
WIDTH_RGB = (0, 230, 255)
MIRRORED_RGB = (0, 140, 160)   # the doubled side of a mirror-side width
TEXT_RGB = (255, 255, 255)
BOX_RGB = (0, 0, 0)
BOX_OPACITY = 0.65
THICKNESS_PER_PX = 1 / 540     # line width per pixel of the frame's short side: 4 px on 4K
FONT_SCALE_PER_PX = 1 / 1200   # Hershey scale per pixel of the short side
GUIDE_OVERHANG = 1.3           # perpendicular guides reach this far beyond the widest half
MIDLINE_SAMPLES = 200


def _caption(record: dict, image_id: str) -> list[str]:
    """The caption lines: image, altitude and the results, each with its unit."""
    return [f"{image_id}",
            f"altitude {record['altitude_m']:.2f} m ({record['altitude_source']})",
            f"length {record['length_m']:.3f} m",
            f"volume {record['volume_m3']:.4f} m^3",
            f"BCI {record['bci']:+.3f}",
            f"mass {record['mass_kg']:.1f} kg"]


def _draw_caption(image: np.ndarray, lines: list[str], scale: float, thickness: int) -> None:
    """Text lines in the top-left corner on a translucent dark box (in place)."""
    font = cv2.FONT_HERSHEY_SIMPLEX
    sizes = [cv2.getTextSize(line, font, scale, thickness)[0] for line in lines]
    line_h = max(h for _, h in sizes) * 1.8
    pad = int(line_h / 2)
    box_w = max(w for w, _ in sizes) + 2 * pad
    box_h = int(line_h * len(lines)) + pad
    box = image[:box_h, :box_w]
    box[:] = (box * (1 - BOX_OPACITY) + np.array(BOX_RGB) * BOX_OPACITY).astype(np.uint8)
    for i, line in enumerate(lines):
        origin = (pad, int(pad + line_h * (i + 0.6)))
        cv2.putText(image, line, origin, font, scale, TEXT_RGB, thickness, cv2.LINE_AA)


def _points(array: np.ndarray) -> np.ndarray:
    """Pixel coordinates as int32 for cv2 (sub-pixel precision is lost, as cv2 draws whole px)."""
    return np.round(array).astype(np.int32)


def draw_receipt(rgb: np.ndarray, annotation: Annotation, result_record: dict) -> np.ndarray:
    """A copy of ``rgb`` (H, W, 3) uint8 with the annotation and the caption drawn on it.

    result_record: the result JSON of the frame (core.measure.records.result_record).
    """
    image = np.ascontiguousarray(rgb, dtype=np.uint8).copy()
    short_side = min(image.shape[:2])
    thickness = max(1, round(short_side * THICKNESS_PER_PX))
    stations = place_stations(annotation.midline_px)
    offsets = edge_offsets(stations, annotation.edges_px)  # (S, 2), NaN where not marked
    mirrored = None if annotation.mirror_side is None else 1 - SIDES.index(annotation.mirror_side)
    if mirrored is not None:  # draw the doubled width: the marked side reflected
        offsets[:, mirrored] = -offsets[:, 1 - mirrored]
    reach = np.nanmax(np.abs(offsets)) if np.isfinite(offsets).any() else 0.05 * stations.length_px
    for point, normal, (off_a, off_b) in zip(stations.points_px, stations.normals, offsets):
        guide = point + np.outer([-reach, reach], normal) * GUIDE_OVERHANG
        cv2.line(image, *map(tuple, _points(guide)), GUIDE_RGB, max(1, thickness // 2),
                 cv2.LINE_AA)
        if np.isfinite(off_a) and np.isfinite(off_b):
            ends = _points(point + np.outer([off_a, off_b], normal))
            cv2.line(image, tuple(ends[0]), tuple(ends[1]), WIDTH_RGB, thickness, cv2.LINE_AA)
            if mirrored is not None:  # the reflected half in a darker tone
                cv2.line(image, tuple(_points(point)), tuple(ends[mirrored]), MIRRORED_RGB,
                         thickness, cv2.LINE_AA)
    spline = midline_spline(annotation.midline_px)
    curve = spline(np.linspace(spline.x[0], spline.x[-1], MIDLINE_SAMPLES))
    cv2.polylines(image, [_points(curve)], False, MIDLINE_RGB, thickness, cv2.LINE_AA)
    _draw_caption(image, _caption(result_record, result_record["input"]),
                  short_side * FONT_SCALE_PER_PX, max(1, thickness // 2))
    return image


def write_png(path: Path, rgb: np.ndarray) -> None:
    """Write an (H, W, 3) uint8 RGB image as PNG, atomically."""
    with atomic_path(Path(path)) as tmp:
        if not cv2.imwrite(str(tmp), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)):
            raise OSError(f"{path}: cannot write the PNG")
