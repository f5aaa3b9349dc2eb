"""Whether a frame's mask shows the whole animal, level and in view.

A dolphin does not change length between frames; its mask does where the animal dives or
pitches (foreshortened: a dive to 1.2 m on the VTK split showed 1.40 m of a 2.50 m animal),
where part of it is under water too deep to see, or where the mask lost a part. Such a mask
would make the fit's animal short and thin (a mask of the front half made the fit 1.42 m long
and 63 % short of volume), so it does not feed the fit: a frame whose mask is shorter, in
metres at the frame's altitude, than ``PARTIAL_SHARE`` of the clip's long frames (their upper
quartile) is left out. And a whole dolphin is 4 to 6 times as long as it is wide at its
widest (true masks of the three bench splits: 4.1–6.2 in every frame); masks that stay under
``WHOLE_ELONGATION`` in every fitted frame show part of one.
"""

import cv2
import numpy as np

PARTIAL_SHARE = 0.8
LONG_QUANTILE = 75
WHOLE_ELONGATION = 3.5


def widest_px(mask: np.ndarray) -> float:
    """The animal's greatest width in a (H, W) bool mask, px: the diameter of the largest
    disc inside it (its widest cross-section, where the body is widest)."""
    rows, cols = np.nonzero(mask)
    crop = np.pad(mask[rows.min():rows.max() + 1, cols.min():cols.max() + 1], 1)
    return 2.0 * float(cv2.distanceTransform(crop.astype(np.uint8), cv2.DIST_L2,
                                             cv2.DIST_MASK_PRECISE).max())


def length_px(mask: np.ndarray) -> float:
    """The long side of the smallest rectangle around a (H, W) bool mask, px (a bent body's
    is a little shorter than its midline: 2–4 % in the splits' turns)."""
    contours, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL,
                                   cv2.CHAIN_APPROX_SIMPLE)
    _centre, sides, _angle = cv2.minAreaRect(np.concatenate(contours))
    return float(max(sides))


def partial(lengths_m: np.ndarray) -> np.ndarray:
    """(T,) bool: the frames whose mask is shorter than ``PARTIAL_SHARE`` of the long ones
    (module doc), given each mask's length in metres."""
    return lengths_m < PARTIAL_SHARE * np.percentile(lengths_m, LONG_QUANTILE)


def elongation(mask: np.ndarray) -> float:
    """How many times as long as it is wide at its widest a (H, W) bool mask is."""
    return length_px(mask) / max(widest_px(mask), 1.0)
