"""The built-in mask tracker: no network, no model weights.

From the seed frame it tracks forwards to the end of the clip, then backwards to the start.
Each frame:

1. **Predict**: the last mask shifted by the last centroid motion (constant velocity).
2. **Classify** near the prediction: every pixel's animal coverage from the running colour
   models of the animal and the water (``colour.coverage``), lightly smoothed; the mask is
   coverage ≥ 0.5 within a margin of the prediction.
3. **Clean**: keep the component that overlaps the prediction most and the parts within a
   couple of pixels of it (flippers, flukes), fill holes.
4. **Check**: the animal is *lost* (dived out of sight, or hidden) when its separation from
   the surrounding water falls below half that of the seed frame, or its area below 40 % of
   the running reference area. Lost frames get no mask.
5. **Update** the colour models, the reference area and the motion; while lost, look for the
   animal again in the whole frame (``seed.find_blobs``) and accept a blob of similar size
   and contrast.
"""

import threading
from dataclasses import dataclass, field

import cv2
import numpy as np

from dolphinfit.core.io.masks import MaskTrack
from dolphinfit.core.progress import ProgressCallback, check_cancel
from dolphinfit.core.segment.colour import ColourModel, coverage, separation, to_lab
from dolphinfit.core.segment.regions import attached, centroid, models_near, shifted, window
from dolphinfit.core.segment.seed import (
    dilate,
    find_blobs,
    refine,
    seed_mask,
    water_model,
)
from dolphinfit.core.segment.segmenter import Frames, Seed
from dolphinfit.core.segment.tracking_loop import check_seed_frame, track_both_ways, track_of


@dataclass(frozen=True)
class TrackerSettings:
    """Tuning of the built-in tracker (defaults measured on the synthetic test clips)."""

    margin_fraction: float = 0.15  # search margin around the prediction, × its longer side
    min_margin_px: int = 6
    smoothing_sigma_px: float = 0.8  # Gaussian smoothing of the coverage map
    gap_px: int = 2  # parts this close to the body belong to it
    model_rate: float = 0.2  # per-frame running update of the colour models and the area
    lost_separation_ratio: float = 0.5  # below half the seed frame's separation: lost
    lost_area_ratio: float = 0.4  # below 40 % of the reference area: lost
    reacquire_area_range: tuple[float, float] = (0.5, 2.0)  # × reference area


@dataclass
class _TrackState:
    """What one tracking pass carries from frame to frame (local to the pass)."""

    mask: np.ndarray | None  # last accepted (H, W) bool mask; None while lost
    animal: ColourModel
    water: ColourModel
    area_px: float
    reference_separation: float
    velocity_px: np.ndarray = field(default_factory=lambda: np.zeros(2))


def colour_follow(frame_rgb: np.ndarray, prediction: np.ndarray, animal: ColourModel,
                  water: ColourModel, settings: TrackerSettings) -> np.ndarray:
    """Steps 2 and 3: the (H, W) mask of coverage ≥ 0.5 near a non-empty ``prediction``,
    attached to it."""
    rows, cols = window(prediction, 0)
    longer_px = max(rows.stop - rows.start, cols.stop - cols.start)
    margin_px = max(settings.min_margin_px, round(settings.margin_fraction * longer_px))
    rows, cols = window(prediction, margin_px)
    cover = cv2.GaussianBlur(coverage(to_lab(frame_rgb[rows, cols]), animal, water), (0, 0),
                             settings.smoothing_sigma_px)
    near = dilate(prediction[rows, cols], margin_px)
    mask = np.zeros_like(prediction)
    mask[rows, cols] = attached((cover >= 0.5) & near, prediction[rows, cols], settings.gap_px)
    return mask


class MaskTracker:
    """The built-in segmenter (implements ``Segmenter``)."""

    def __init__(self, settings: TrackerSettings = TrackerSettings()) -> None:
        self.settings = settings

    def segment(self, frames: Frames, seed: Seed, progress: ProgressCallback | None = None,
                cancel: threading.Event | None = None) -> MaskTrack:
        """Masks for every frame of ``frames``, tracked from ``seed`` (see the module doc).

        InputError if the seed finds no animal; core.progress.Cancelled once ``cancel`` is set
        (TrackingCancelled, with the frames tracked, once tracking has begun).
        """
        num_frames = len(frames)
        check_seed_frame(seed, num_frames)
        check_cancel(cancel)
        first = frames[seed.frame_idx]
        height, width = first.shape[:2]
        mask = seed_mask(first, seed)
        animal, water = models_near(first, mask)
        return track_both_ways(
            frames, seed.frame_idx, mask, range(num_frames),
            lambda: _TrackState(mask, animal, water, float(mask.sum()),
                                separation(animal, water)),
            self._next,
            lambda crops: track_of(crops, num_frames, width, height,
                                   f"built-in tracker from {seed}"),
            progress, cancel)

    def _next(self, frame_rgb: np.ndarray, state: _TrackState) -> np.ndarray | None:
        """The mask in the next frame (None if lost), updating ``state``."""
        if state.mask is None:
            mask = self._reacquire(frame_rgb, state)
        else:
            mask = self._follow(frame_rgb, state)
        if mask is None:
            state.mask = None
            return None
        if state.mask is not None:
            state.velocity_px = centroid(mask) - centroid(state.mask)
        else:
            state.velocity_px = np.zeros(2)
        animal, water = models_near(frame_rgb, mask)
        rate = self.settings.model_rate
        state.animal = state.animal.blend(animal, rate)
        state.water = state.water.blend(water, rate)
        state.area_px = (1 - rate) * state.area_px + rate * float(np.count_nonzero(mask))
        state.mask = mask
        return mask

    def _follow(self, frame_rgb: np.ndarray, state: _TrackState) -> np.ndarray | None:
        """Classify near the predicted mask; None if the result says the animal is lost."""
        prediction = shifted(state.mask, state.velocity_px)
        if not prediction.any():
            return None
        mask = colour_follow(frame_rgb, prediction, state.animal, state.water, self.settings)
        return mask if self._is_animal(frame_rgb, mask, state) else None

    def _is_animal(self, frame_rgb: np.ndarray, mask: np.ndarray, state: _TrackState) -> bool:
        """Whether ``mask`` still shows the animal: enough area and contrast to the water."""
        settings = self.settings
        if np.count_nonzero(mask) < max(1.0, settings.lost_area_ratio * state.area_px):
            return False
        contrast = separation(*models_near(frame_rgb, mask))
        return contrast >= settings.lost_separation_ratio * state.reference_separation

    def _reacquire(self, frame_rgb: np.ndarray, state: _TrackState) -> np.ndarray | None:
        """While lost: the first dolphin-like blob of about the reference size, refined."""
        low, high = self.settings.reacquire_area_range
        lab = to_lab(frame_rgb)
        for blob in find_blobs(lab, water_model(lab)):
            if low * state.area_px <= blob.area_px <= high * state.area_px:
                mask = refine(lab, blob.mask)
                if mask.any() and self._is_animal(frame_rgb, mask, state):
                    return mask
        return None
