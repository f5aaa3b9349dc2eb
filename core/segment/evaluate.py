"""Measuring a segmenter against true masks: per-frame intersection over union, and how far
out or in its outline lies.

``measure_tracker`` runs on any clip with a folder of true masks (``%06d.png``): the synthetic
clips of the tests today, ``core/synth`` clips once they exist. IoU is ``core.iou``'s: a frame
where both the truth and the result are empty (the animal correctly reported lost) scores 1; a
frame where only one of them is empty scores 0.
"""

from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.io.masks import MaskTrack, read_png_folder
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.segment.segmenter import BoxSeed, Seed, Segmenter
from dolphinfit.core.segment.tracker import MaskTracker


def track_iou(result: MaskTrack, truth: MaskTrack) -> np.ndarray:
    """(T,) float64 IoU of each frame's masks."""
    return np.array([mask_iou(result.mask(t), truth.mask(t)) for t in range(truth.num_frames)])


def outline_offset_px(result: np.ndarray, truth: np.ndarray) -> float:
    """How far the result's outline lies outside (+) or inside (−) the truth's on average, in
    pixels: the difference of their areas over the length of the truth's outline (NaN where
    the truth is empty). Volume follows it closely: every width is two outlines apart, so at
    the suite's pixel size a tenth of a pixel is 1.5–2.5 % of volume (docs/explanation/accuracy.md)."""
    contours, _ = cv2.findContours(truth.astype(np.uint8), cv2.RETR_EXTERNAL,
                                   cv2.CHAIN_APPROX_NONE)
    length = sum(cv2.arcLength(contour, True) for contour in contours)
    if length == 0:
        return float("nan")
    return (int(np.count_nonzero(result)) - int(np.count_nonzero(truth))) / length


def box_seed_from(truth: MaskTrack, frame_idx: int | None = None) -> BoxSeed:
    """A user's box around the animal (the bounding box of its true mask) in frame
    ``frame_idx``, by default the first frame where it is visible."""
    if frame_idx is None:
        frame_idx = int(np.flatnonzero(truth.is_visible)[0])
    rows, cols = np.nonzero(truth.mask(frame_idx))
    return BoxSeed(int(cols.min()), int(rows.min()), int(np.ptp(cols)) + 1,
                   int(np.ptp(rows)) + 1, frame_idx)


def measure_tracker(clip_path: Path | str, true_masks_dir: Path | str,
                    segmenter: Segmenter | None = None, seed: Seed | None = None) -> np.ndarray:
    """(T,) per-frame IoU of ``segmenter`` (default: the built-in tracker) on a clip.

    ``seed`` defaults to a box around the true mask in its first visible frame, as a user
    would draw it.
    """
    clip = open_clip(clip_path)
    truth = read_png_folder(Path(true_masks_dir), clip)
    segmenter = segmenter or MaskTracker()
    with VideoReader(clip) as frames:
        result = segmenter.segment(frames, seed or box_seed_from(truth))
    return track_iou(result, truth)
