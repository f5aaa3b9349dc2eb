"""The automatic seed: the animals the network sees in a frame, best first.

Candidates come from the salient network looking at the whole frame (a large animal, a whale
near the drone) and at overlapping square tiles ``tile_fraction`` of its shorter side (a
small one: in a whole-height tile a 2 m animal from 25 m is too small for the network to
see; where the camera and altitude are known, tiles are at most twice the longest animal
expected, so that a 10-px wide animal from 42 m on a 720p frame fills enough of one), and
from the built-in colour detector (``seed.find_blobs``: a dark animal over sand, which the
network hardly sees). Each passes the shape tests of one animal seen from above
(size, elongation, fill). Where the camera and altitude are known, the seed carries the
lengths in pixels an animal can have (``AutoSeed.length_px``), and a candidate outside them
(a wake, a boat, a burned-in caption) is not an animal. The same animal found in several
tiles is one candidate (the best-scoring look). Candidates are ranked in tiers, then by
score (the mean saliency × √area: the most salient and largest first): the network's lone
animals, the colour detector's blobs, then the network's less elongated components and those
a tile's edge cuts (a part of an animal in glitter or at the edge of a tile). A seagrass
patch or a glitter field the network marks is wider than a dolphin.
"""

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from dolphinfit.core.segment.seed import (
    MAX_AREA_FRACTION, MAX_ELONGATION, MIN_AREA_FRACTION, MIN_ELONGATION, MIN_FILL,
    find_blobs, refine, shape_of, water_model,
)
from dolphinfit.core.segment.colour import to_lab

PAIR_MAX_ELONGATION = 3.5   # below this a component may be two animals side by side
LENGTH_SLACK = (0.6, 1.4)   # a candidate's length may lie this far outside the expected range
SAME_ANIMAL_SHARE = 0.5     # candidates sharing this much of the smaller are one animal


LONE, COLOUR, PART = 0, 1, 2   # tiers, best first (module doc)
MAX_COLOUR_BLOBS = 3           # the colour detector's best blobs considered
TILE_ANIMAL_LENGTHS = 2.0      # a tile is at most this many of the longest expected animal
MIN_TILE_PX = 160              # half the network's input: tiles are upscaled at most 2×
# Bottlenose dolphins from calf to the largest adult: what the automatic seed looks for
DOLPHIN_LENGTH_M = (1.0, 4.0)


@dataclass(frozen=True, eq=False)
class Candidate:
    """An animal the automatic seed found: its (H, W) bool mask, tier, score, length along
    its principal axis (px)."""

    mask: np.ndarray
    tier: int
    score: float
    length_px: float

    def centre_px(self) -> tuple[float, float]:
        """(x, y) of the mask's centroid."""
        rows, cols = np.nonzero(self.mask)
        return float(cols.mean()), float(rows.mean())


def expected_length_px(focal_px: float, altitudes_m: np.ndarray,
                       length_m: tuple[float, float]) -> tuple[float, float] | None:
    """(shortest, longest) length in pixels of an animal ``length_m`` long seen from the
    clip's altitudes (its lowest and highest); None without a valid altitude."""
    valid = altitudes_m[np.isfinite(altitudes_m) & (altitudes_m > 0)]
    if not valid.size:
        return None
    return length_m[0] * focal_px / valid.max(), length_m[1] * focal_px / valid.min()


def extent_px(mask: np.ndarray) -> float:
    """The mask's extent along its principal axis, px (its length, for an animal)."""
    rows, cols = np.nonzero(mask)
    points = np.stack([cols, rows], axis=1).astype(np.float64)
    if len(points) < 3:
        return float(len(points))
    centred = points - points.mean(axis=0)
    _, _, axes = np.linalg.svd(centred, full_matrices=False)
    return float(np.ptp(centred @ axes[0]) + 1.0)


def is_animal_shaped(mask: np.ndarray, frame_area_px: int) -> bool:
    """Whether a component has the size and shape of an animal seen from above (or of a
    part of one: lone animals are at least ``PAIR_MAX_ELONGATION`` long)."""
    area, elongation, fill = shape_of(mask)
    return (MIN_AREA_FRACTION * frame_area_px <= area <= MAX_AREA_FRACTION * frame_area_px
            and MIN_ELONGATION <= elongation <= MAX_ELONGATION and fill >= MIN_FILL)


def is_lone(mask: np.ndarray) -> bool:
    """Whether an animal-shaped component is long enough to be one animal, not two."""
    return shape_of(mask)[1] >= PAIR_MAX_ELONGATION


def fits_length(length_px: float, expected: tuple[float, float] | None) -> bool:
    """Whether a length lies within the expected range, with ``LENGTH_SLACK``."""
    return expected is None or \
        expected[0] * LENGTH_SLACK[0] <= length_px <= expected[1] * LENGTH_SLACK[1]


def cut_by_window(mask: np.ndarray, rows: slice, cols: slice) -> bool:
    """Whether a (frame-sized) mask found in a window reaches a side of the window that is
    not the frame's edge: the window cut the animal off."""
    height, width = mask.shape
    sides = [mask[rows.start, cols]] if rows.start > 0 else []
    sides += [mask[rows.stop - 1, cols]] if rows.stop < height else []
    sides += [mask[rows, cols.start]] if cols.start > 0 else []
    sides += [mask[rows, cols.stop - 1]] if cols.stop < width else []
    return any(side.any() for side in sides)


def tile_starts(length_px: int, side_px: int) -> list[int]:
    """Starts of the fewest tiles of ``side_px`` that cover ``length_px`` with overlap."""
    count = int(np.ceil(length_px / side_px))
    return [round(i * (length_px - side_px) / max(count - 1, 1)) for i in range(count)] \
        if count > 1 else [0]


def tile_side_px(height: int, width: int, tile_fraction: float,
                 expected: tuple[float, float] | None) -> int:
    """The side of the square tiles: ``tile_fraction`` of the frame's shorter side, or
    ``TILE_ANIMAL_LENGTHS`` times the longest expected animal where that is smaller (a small
    animal from high up fills too little of a larger tile for the network to see it), never
    under ``MIN_TILE_PX``."""
    side = tile_fraction * min(height, width)
    if expected is not None:
        side = min(side, max(TILE_ANIMAL_LENGTHS * expected[1], MIN_TILE_PX))
    return round(side)


def salient_candidates(frame_rgb: np.ndarray, saliency_of: Callable[[np.ndarray], np.ndarray],
                       tile_fraction: float, threshold: float,
                       expected: tuple[float, float] | None) -> list[Candidate]:
    """The network's animal-shaped components in the whole frame and in tiles (module
    doc)."""
    height, width = frame_rgb.shape[:2]
    side = tile_side_px(height, width, tile_fraction, expected)
    windows = [(slice(0, height), slice(0, width))] + [
        (slice(row0, row0 + side), slice(col0, col0 + side))
        for row0 in tile_starts(height, side) for col0 in tile_starts(width, side)]
    return [candidate for rows, cols in windows for candidate in
            window_candidates(frame_rgb, rows, cols, saliency_of, threshold, expected)]


def window_candidates(frame_rgb: np.ndarray, rows: slice, cols: slice,
                      saliency_of: Callable[[np.ndarray], np.ndarray], threshold: float,
                      expected: tuple[float, float] | None) -> list[Candidate]:
    """The network's animal-shaped components in one window of the frame, as frame-sized
    candidates (one look of the network)."""
    height, width = frame_rgb.shape[:2]
    saliency = saliency_of(np.ascontiguousarray(frame_rgb[rows, cols]))
    count, labels = cv2.connectedComponents((saliency >= threshold).astype(np.uint8),
                                            connectivity=8)
    found = []
    for label in range(1, count):
        blob = labels == label
        if not is_animal_shaped(blob, height * width):
            continue
        mask = np.zeros((height, width), bool)
        mask[rows, cols] = blob
        length = extent_px(mask)
        if fits_length(length, expected):
            score = float(saliency[blob].mean() * np.sqrt(np.count_nonzero(blob)))
            whole = is_lone(blob) and not cut_by_window(mask, rows, cols)
            found.append(Candidate(mask, LONE if whole else PART, score, length))
    return found


def colour_candidates(frame_rgb: np.ndarray,
                      expected: tuple[float, float] | None) -> list[Candidate]:
    """The colour detector's best dark, elongated blobs, refined (module doc)."""
    lab = to_lab(frame_rgb)
    found = []
    for blob in find_blobs(lab, water_model(lab))[:MAX_COLOUR_BLOBS]:
        mask = refine(lab, blob.mask)
        length = extent_px(mask) if mask.any() else 0.0
        if mask.any() and fits_length(length, expected):
            found.append(Candidate(mask, COLOUR, blob.score, length))
    return found


def same_animal(mask: np.ndarray, other: np.ndarray) -> bool:
    """Whether two masks share ``SAME_ANIMAL_SHARE`` of the smaller: one animal."""
    smaller = min(np.count_nonzero(mask), np.count_nonzero(other))
    return np.count_nonzero(mask & other) >= SAME_ANIMAL_SHARE * smaller


def distinct(candidates: list[Candidate]) -> list[Candidate]:
    """Best first, one per animal: a candidate that is the ``same_animal`` as a better one
    is left out."""
    kept: list[Candidate] = []
    for candidate in sorted(candidates, key=lambda c: (c.tier, -c.score)):
        if not any(same_animal(candidate.mask, other.mask) for other in kept):
            kept.append(candidate)
    return kept


def find_animals(frame_rgb: np.ndarray, saliency_of: Callable[[np.ndarray], np.ndarray],
                 tile_fraction: float, threshold: float,
                 expected: tuple[float, float] | None = None) -> list[Candidate]:
    """Every animal the automatic seed finds in a frame, best first (module doc)."""
    found = salient_candidates(frame_rgb, saliency_of, tile_fraction, threshold, expected)
    return distinct(found + colour_candidates(frame_rgb, expected))


def scan_order(chosen: Sequence[int], first: int, most: int) -> list[int]:
    """``first``, then up to ``most`` − 1 of the ``chosen`` frames spread evenly over them
    (later ones first), none twice."""
    others = [t for t in chosen if t > first] + [t for t in reversed(chosen) if t < first]
    if len(others) >= most:
        others = [others[i] for i in np.linspace(0, len(others) - 1, most - 1).round()
                  .astype(int)]
    return list(dict.fromkeys([first, *others]))


def describe(candidates: list[Candidate], frame_idx: int) -> str:
    """One line for the user: how many animals, which was taken, where the others are."""
    taken = candidates[0]
    x, y = taken.centre_px()
    line = (f"automatic seed, frame {frame_idx}: {len(candidates)} animal"
            f"{'s' if len(candidates) != 1 else ''} seen; took the "
            f"{('most salient', 'darkest', 'most salient')[taken.tier]} one at "
            f"({x:.0f}, {y:.0f}), {taken.length_px:.0f} px long")
    others = "; ".join(f"({cx:.0f}, {cy:.0f})" for cx, cy in
                       (c.centre_px() for c in candidates[1:]))
    return line + (f"; others at {others}" if others else "")
