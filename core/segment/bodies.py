"""One animal out of touching ones: a component the network marks around two bodies split
between them, and how much a mask looks like one lone dolphin."""

import cv2
import numpy as np

from dolphinfit.core.segment.auto_seed import PAIR_MAX_ELONGATION
from dolphinfit.core.segment.net_settings import PAIR_AREA_RATIO
from dolphinfit.core.segment.regions import attached
from dolphinfit.core.segment.seed import shape_of

CORE_LEVELS = (0.9, 0.99, 0.999)  # stricter probability levels where touching bodies part
MIN_CORE_SHARE = 0.25  # a second core this large (× the largest) is a second animal
DOLPHIN_ELONGATION = 5.0  # a lone dolphin's moment elongation: 4.2–6.1 on the bench suite


def nearer_to(region: np.ndarray, own: np.ndarray, other: np.ndarray) -> np.ndarray:
    """The pixels of ``region`` at least as close to ``own`` as to ``other`` (both non-empty
    bool masks): a Voronoi split of two touching animals between what is known of each."""
    to_own = cv2.distanceTransform((~own).astype(np.uint8), cv2.DIST_L2, 3)
    to_other = cv2.distanceTransform((~other).astype(np.uint8), cv2.DIST_L2, 3)
    return region & (to_own <= to_other)


def dolphin_unlikeness(mask: np.ndarray) -> float:
    """How far a mask's elongation is from a lone dolphin's seen from above (|log| of the
    ratio to ``DOLPHIN_ELONGATION``); infinite for an empty mask."""
    elongation = shape_of(mask)[1]
    return abs(float(np.log(elongation / DOLPHIN_ELONGATION))) if elongation > 0 else np.inf


def own_body(component: np.ndarray, hint: np.ndarray, saliency: np.ndarray,
             expected_area_px: float | None = None) -> np.ndarray:
    """The body that ``hint`` (a click, an earlier mask) marks when ``component`` holds
    several touching animals.

    A lone dolphin seen from above is long and thin (moment elongation 4.2–6.1 on the bench
    suite, turns included); two side by side are not, or are larger than one. Only such a
    component is split. Between two touching animals the network's probability dips: at a
    stricter level the component falls apart into one core per body (a second core at least
    ``MIN_CORE_SHARE`` of the largest; a dolphin's flukes or flippers are smaller). The hinted
    body's core is the one the hint covers most (else the one nearest to it), and each pixel
    goes to the nearest core. One core at every level: the component."""
    area, elongation, _ = shape_of(component)
    larger = expected_area_px is not None and area > PAIR_AREA_RATIO * expected_area_px
    if elongation >= PAIR_MAX_ELONGATION and not larger:
        return component
    for level in CORE_LEVELS:
        count, cores, stats, _ = cv2.connectedComponentsWithStats(
            (component & (saliency >= level)).astype(np.uint8), connectivity=8)
        if count < 3:
            continue
        areas = stats[1:, cv2.CC_STAT_AREA]
        bodies = 1 + np.flatnonzero(areas >= MIN_CORE_SHARE * areas.max())
        if len(bodies) >= 2:
            return _split(component, hint, cores, bodies)
    return component


def _split(component: np.ndarray, hint: np.ndarray, cores: np.ndarray,
           bodies: np.ndarray) -> np.ndarray:
    """``own_body``'s split once the cores of the bodies are known."""
    body_cores = np.isin(cores, bodies)
    covered = np.bincount(cores[hint & body_cores], minlength=cores.max() + 1)
    if covered.any():
        label = int(np.argmax(covered))
    else:
        core_rows, core_cols = np.nonzero(body_cores)
        hint_row, hint_col = np.argwhere(hint).mean(axis=0)
        nearest = np.argmin(np.hypot(core_rows - hint_row, core_cols - hint_col))
        label = cores[core_rows[nearest], core_cols[nearest]]
    own = cores == label
    return attached(nearer_to(component, own, body_cores & ~own), own, 1)
