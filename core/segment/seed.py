"""Seeding the tracker: the animal's mask in one frame, from a click, a box, or by itself.

Automatic detection looks for the most dolphin-like blob: pixels far from the water's colour
and darker than it, grouped into components that are elongated and ellipse-like (a dolphin
from above), scored by contrast and size. A box seed runs GrabCut inside the box; a click
picks the detected blob under (or nearest to) it. Every seed ends with the same coverage
classification that the tracker uses (``colour.coverage``), so the first mask and the tracked
ones agree.
"""

from dataclasses import dataclass

import cv2
import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.segment.colour import ColourModel, coverage, to_lab
from dolphinfit.core.segment.segmenter import AutoSeed, BoxSeed, PointSeed, Seed

WATER_TRIM_QUANTILE = 0.95  # the water model drops the 5 % of pixels least like it (animal, glints)
WATER_SAMPLE_STEP = 4  # fit the water model on every 4th pixel in each direction
DETECT_DISTANCE = 4.0  # Mahalanobis distance from the water above which a pixel may be animal
# Of the frame: a 2.5 m dolphin at 20 m on a 1920×1080 frame (about 170 px long, DESIGN.md §3)
# covers about 0.2 %; a quarter of that still counts.
MIN_AREA_FRACTION = 0.0005
MAX_AREA_FRACTION = 0.2
# Length over width of the blob's moment ellipse: about 4–5 for a dolphin seen from above
# (maximum width about 0.18 of body length, reference/morphometrics.md §4), with slack for
# bent bodies, flippers, missing flukes and noisy outlines.
MIN_ELONGATION = 2.0
MAX_ELONGATION = 12.0
MIN_FILL = 0.55  # blob area over its moment ellipse's area: 1 for a filled ellipse
GRABCUT_ITERATIONS = 5
DISTANCE_FROM_PX = 24  # ``dilate`` by the distance transform from this radius
BOX_CONTEXT_FRACTION = 0.25  # GrabCut also sees this much of the box's size around it
RING_INNER_PX, RING_OUTER_PX = 2, 10  # the water ring around a blob, pixels from its outline
# The animal's colour model comes from the ring of pixels just inside its outline (the second
# pixel in): outline pixels blend that colour (lighter flanks, on a dolphin) with the water's,
# so the coverage scale must run from the water to the rim, not to the darker back. Measured
# on the synthetic clips: a 1-px rim gave 0.90–0.93 mean IoU, a 1–4 px rim 0.88–0.92, and a
# rim that includes the outline pixels themselves was unstable.
RIM_INNER_PX, RIM_OUTER_PX = 1, 2
MEDIAN_KSIZE = 3  # detection ignores single-pixel glints and noise
POINT_SEARCH_FRACTION = 0.1  # a click may miss the blob by this much of the frame's diagonal


@dataclass(frozen=True, eq=False)
class Blob:
    """A candidate animal: its (H, W) bool mask, area (px), elongation and score."""

    mask: np.ndarray
    area_px: int
    elongation: float
    score: float


def _kernel(radius_px: int) -> np.ndarray:
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius_px + 1, 2 * radius_px + 1))


def dilate(mask: np.ndarray, radius_px: int) -> np.ndarray:
    """(H, W) bool mask grown by a disc of ``radius_px``. Only the mask's bounding box grown
    by the radius is dilated (nothing beyond it can change): a small animal's mask in a 4K
    frame costs what its box does, not what the frame does. From ``DISTANCE_FROM_PX`` the
    disc is the pixels within the radius by the exact Euclidean distance transform, whose
    cost does not grow with the radius (a 100-px disc around a 400-px animal: 2 ms against
    138 ms by the kernel; the two differ on 0.2 % of the grown pixels, at its rim)."""
    grown = np.zeros(mask.shape, bool)
    col0, row0, width, height = cv2.boundingRect(mask.view(np.uint8) if mask.dtype == bool
                                                 else mask.astype(np.uint8))
    if width == 0:
        return grown
    rows = slice(max(0, row0 - radius_px), min(mask.shape[0], row0 + height + radius_px))
    cols = slice(max(0, col0 - radius_px), min(mask.shape[1], col0 + width + radius_px))
    region = mask[rows, cols].astype(np.uint8)
    if radius_px >= DISTANCE_FROM_PX:
        distance = cv2.distanceTransform(1 - region, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
        grown[rows, cols] = distance <= radius_px
    else:
        grown[rows, cols] = cv2.dilate(region, _kernel(radius_px)).astype(bool)
    return grown


def erode(mask: np.ndarray, radius_px: int) -> np.ndarray:
    """(H, W) bool mask shrunk by a disc of ``radius_px``."""
    return cv2.erode(mask.astype(np.uint8), _kernel(radius_px)).astype(bool)


def water_model(lab: np.ndarray) -> ColourModel:
    """The water's colour model from a whole (H, W, 3) Lab frame, ignoring what is unlike it."""
    pixels = lab[::WATER_SAMPLE_STEP, ::WATER_SAMPLE_STEP].reshape(-1, 3)
    first = ColourModel.fit(pixels)
    distance = first.distance(pixels)
    return ColourModel.fit(pixels[distance <= np.quantile(distance, WATER_TRIM_QUANTILE)])


def shape_of(mask: np.ndarray) -> tuple[int, float, float]:
    """(area px, elongation, fill) of a bool mask from its second moments."""
    moments = cv2.moments(mask.astype(np.uint8), binaryImage=True)
    area = moments["m00"]
    if area < 3:
        return int(area), 0.0, 0.0
    cov = np.array([[moments["mu20"], moments["mu11"]], [moments["mu11"], moments["mu02"]]])
    minor, major = np.sqrt(np.maximum(np.linalg.eigvalsh(cov / area), 1e-12))
    # a filled ellipse with semi-axes (a, b) has moment SDs (a / 2, b / 2) and area π·a·b
    return int(area), float(major / minor), float(area / (np.pi * 4 * major * minor))


def find_blobs(lab: np.ndarray, water: ColourModel) -> list[Blob]:
    """Dolphin-like blobs in a (H, W, 3) Lab frame, best first."""
    lab = cv2.medianBlur(lab, MEDIAN_KSIZE)
    distance = water.distance(lab)
    darker = lab[..., 0] < water.mean[0]
    candidate = ((distance > DETECT_DISTANCE) & darker).astype(np.uint8)
    candidate = cv2.morphologyEx(candidate, cv2.MORPH_OPEN, _kernel(1))
    count, labels, stats, _ = cv2.connectedComponentsWithStats(candidate, connectivity=8)
    frame_area = lab.shape[0] * lab.shape[1]
    blobs = []
    for label in range(1, count):
        area = stats[label, cv2.CC_STAT_AREA]
        if not MIN_AREA_FRACTION * frame_area <= area <= MAX_AREA_FRACTION * frame_area:
            continue
        mask = fill_holes(labels == label)
        _, elongation, fill = shape_of(mask)
        if MIN_ELONGATION <= elongation <= MAX_ELONGATION and fill >= MIN_FILL:
            score = float(distance[mask].mean() * np.sqrt(area))
            blobs.append(Blob(mask, int(area), elongation, score))
    return sorted(blobs, key=lambda b: -b.score)


def largest_component(mask: np.ndarray) -> np.ndarray:
    """The largest 8-connected component of a bool mask, holes filled (empty stays empty)."""
    count, labels, stats, _ = cv2.connectedComponentsWithStats(mask.astype(np.uint8), 8)
    if count < 2:
        return np.zeros_like(mask, dtype=bool)
    keep = labels == 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
    return fill_holes(keep)


def fill_holes(mask: np.ndarray) -> np.ndarray:
    """A bool mask with its enclosed holes filled."""
    contours, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL,
                                   cv2.CHAIN_APPROX_NONE)
    filled = np.zeros(mask.shape, np.uint8)
    cv2.drawContours(filled, contours, -1, 1, thickness=cv2.FILLED)
    return filled.astype(bool)


def colour_models(lab: np.ndarray, mask: np.ndarray) -> tuple[ColourModel, ColourModel]:
    """(animal, water) models: pixels in a rim just inside the mask and a ring around it."""
    rim = erode(mask, RIM_INNER_PX) & ~erode(mask, RIM_OUTER_PX)
    ring = dilate(mask, RING_OUTER_PX) & ~dilate(mask, RING_INNER_PX)
    return ColourModel.fit(lab[rim if rim.any() else mask]), ColourModel.fit(lab[ring])


def refine(lab: np.ndarray, rough: np.ndarray) -> np.ndarray:
    """The coverage ≥ 0.5 mask of the animal near a rough mask, from its own colour models."""
    animal, water = colour_models(lab, rough)
    near = dilate(rough, RING_OUTER_PX)
    return largest_component((coverage(lab, animal, water) >= 0.5) & near)


def _grabcut_box(frame_rgb: np.ndarray, seed: BoxSeed) -> np.ndarray:
    """GrabCut inside the box (with context around it): the rough (H, W) bool mask."""
    height, width = frame_rgb.shape[:2]
    pad_x = int(BOX_CONTEXT_FRACTION * seed.width_px)
    pad_y = int(BOX_CONTEXT_FRACTION * seed.height_px)
    x0, y0 = max(0, seed.x_px - pad_x), max(0, seed.y_px - pad_y)
    x1 = min(width, seed.x_px + seed.width_px + pad_x)
    y1 = min(height, seed.y_px + seed.height_px + pad_y)
    roi = np.ascontiguousarray(frame_rgb[y0:y1, x0:x1])
    labels = np.zeros(roi.shape[:2], np.uint8)
    rect = (seed.x_px - x0, seed.y_px - y0, seed.width_px, seed.height_px)
    cv2.grabCut(roi, labels, rect, np.zeros((1, 65)), np.zeros((1, 65)), GRABCUT_ITERATIONS,
                cv2.GC_INIT_WITH_RECT)
    rough = np.zeros((height, width), bool)
    rough[y0:y1, x0:x1] = (labels == cv2.GC_FGD) | (labels == cv2.GC_PR_FGD)
    return largest_component(rough)


def _blob_at(blobs: list[Blob], seed: PointSeed, frame_shape: tuple[int, ...]) -> Blob | None:
    """The blob under the click, else the nearest one within the search radius."""
    col, row = int(round(seed.x_px)), int(round(seed.y_px))
    inside = [b for b in blobs if 0 <= row < frame_shape[0] and 0 <= col < frame_shape[1]
              and b.mask[row, col]]
    if inside:
        return inside[0]
    radius = POINT_SEARCH_FRACTION * np.hypot(*frame_shape[:2])
    nearest = None
    for blob in blobs:
        rows, cols = np.nonzero(blob.mask)
        gap = np.min(np.hypot(rows - seed.y_px, cols - seed.x_px))
        if gap <= radius and (nearest is None or gap < nearest[0]):
            nearest = (gap, blob)
    return None if nearest is None else nearest[1]


def _check_inside(seed: Seed, frame_shape: tuple[int, ...]) -> None:
    height, width = frame_shape[:2]
    if isinstance(seed, PointSeed):
        inside = 0 <= seed.x_px < width and 0 <= seed.y_px < height
    elif isinstance(seed, BoxSeed):
        inside = (seed.width_px > 0 and seed.height_px > 0 and seed.x_px >= 0
                  and seed.y_px >= 0 and seed.x_px + seed.width_px <= width
                  and seed.y_px + seed.height_px <= height)
    else:
        inside = True
    if not inside:
        raise InputError(f"seed {seed}: outside the {width}x{height} px frame")


def seed_mask(frame_rgb: np.ndarray, seed: Seed) -> np.ndarray:
    """The animal's (H, W) bool mask in the seed frame; InputError if none is found."""
    _check_inside(seed, frame_rgb.shape)
    lab = to_lab(frame_rgb)
    if isinstance(seed, BoxSeed):
        rough = _grabcut_box(frame_rgb, seed)
    else:
        blobs = find_blobs(lab, water_model(lab))
        blob = _blob_at(blobs, seed, lab.shape) if isinstance(seed, PointSeed) else \
            (blobs[0] if blobs else None)
        rough = blob.mask if blob is not None else np.zeros(lab.shape[:2], bool)
    mask = refine(lab, rough) if rough.any() else rough
    if not mask.any():
        what = "no dark, elongated animal found" + ("" if isinstance(seed, AutoSeed)
                                                     else " at the seed")
        raise InputError(f"frame {seed.frame_idx}: {what} ({seed})")
    return mask
