"""Small pictures of an animal in its scored frames, for the app's frame picker."""

from collections.abc import Sequence

import cv2
import numpy as np

from dolphinfit.core.io.frame_source import FrameSource
from dolphinfit.core.scan.frame_scores import FrameScore

CROP_LENGTHS = 1.3   # the crop's side, in the animal's length: the whole animal and some water


def animal_crop(frame: np.ndarray, centre_px: tuple[float, float], length_px: float,
                size_px: int) -> np.ndarray:
    """A (size_px, size_px, 3) square of ``frame`` centred on the animal, CROP_LENGTHS of its
    length across (at least 16 px), padded with black beyond the frame's edge."""
    side = max(16, int(round(CROP_LENGTHS * length_px)))
    height, width = frame.shape[:2]
    left = int(round(centre_px[0] - side / 2))
    top = int(round(centre_px[1] - side / 2))
    crop = np.zeros((side, side, 3), np.uint8)
    rows = slice(max(top, 0), min(top + side, height))
    cols = slice(max(left, 0), min(left + side, width))
    if rows.start < rows.stop and cols.start < cols.stop:
        crop[rows.start - top:rows.stop - top, cols.start - left:cols.stop - left] = \
            frame[rows, cols]
    return cv2.resize(crop, (size_px, size_px), interpolation=cv2.INTER_AREA)


def thumbnails(source: FrameSource, scores: Sequence[FrameScore],
               size_px: int) -> dict[tuple[int, int], np.ndarray]:
    """The animal's crop for each score, by (animal, frame); each frame decoded once, in
    order."""
    by_frame: dict[int, list[FrameScore]] = {}
    for score in scores:
        by_frame.setdefault(score.frame_idx, []).append(score)
    return {(score.animal_id, frame_idx): animal_crop(
                frame, (score.centre_x_px, score.centre_y_px), score.length_px, size_px)
            for frame_idx, frame in source.frames(sorted(by_frame))
            for score in by_frame[frame_idx]}
