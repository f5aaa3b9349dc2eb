"""Tests for core/segment: the built-in tracker on synthetic clips with true masks (see
conftest.py), its seeds, progress and cancel, and the segmenter interface."""

import threading

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import MaskTrack, read_png_folder
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.progress import Cancelled
from dolphinfit.core.segment.evaluate import (
    box_seed_from, mask_iou, measure_tracker, outline_offset_px, track_iou,
)
from dolphinfit.core.segment.segmenter import AutoSeed, PointSeed, TrackingCancelled
from dolphinfit.core.segment.tracker import MaskTracker

CALM_MIN_MEAN_IOU = 0.85  # the aim for calm water
ROUGH_MIN_MEAN_IOU = 0.80


def _truth(clips, kind: str) -> MaskTrack:
    clip_path, masks_dir = clips[kind]
    return read_png_folder(masks_dir, open_clip(clip_path))


def test_calm_water_box_seed_meets_the_aim(synthetic_clips):
    """Calm water, seeded by a box around the first true mask: mean IoU ≥ 0.85."""
    iou = measure_tracker(*synthetic_clips["calm"])
    assert iou.shape == (48,)
    assert iou.mean() >= CALM_MIN_MEAN_IOU and iou.min() >= 0.8


def test_rough_water_with_waves_and_glints(synthetic_clips):
    """Rough water (waves, glints over the animal, more noise): mean IoU ≥ 0.80."""
    assert measure_tracker(*synthetic_clips["rough"]).mean() >= ROUGH_MIN_MEAN_IOU


@pytest.mark.parametrize("kind", ["calm", "rough"])
def test_automatic_seed_finds_the_animal(synthetic_clips, kind):
    """With no seed from the user the most dolphin-like blob is the animal."""
    iou = measure_tracker(*synthetic_clips[kind], seed=AutoSeed())
    assert iou.mean() >= ROUGH_MIN_MEAN_IOU


def test_point_seed_on_the_animal(synthetic_clips):
    """A click on the animal's centre seeds as well as a box."""
    truth = _truth(synthetic_clips, "calm")
    rows, cols = np.nonzero(truth.mask(0))
    iou = measure_tracker(*synthetic_clips["calm"],
                          seed=PointSeed(float(cols.mean()), float(rows.mean())))
    assert iou.mean() >= CALM_MIN_MEAN_IOU


@pytest.mark.parametrize("kind", ["calm-dive", "rough-dive"])
def test_dive_is_marked_lost_and_found_again(synthetic_clips, kind):
    """While the animal is under, frames are marked lost; it is tracked again after."""
    clip_path, _ = synthetic_clips[kind]
    truth = _truth(synthetic_clips, kind)
    with VideoReader(clip_path) as frames:
        result = MaskTracker().segment(frames, box_seed_from(truth))
    disagree = np.flatnonzero(result.is_visible != truth.is_visible)
    assert len(disagree) <= 2 and np.all(np.isin(disagree, [23, 24, 38, 39]))
    assert not result.is_visible[25:38].any() and result.is_visible[40:].all()
    assert track_iou(result, truth).mean() >= ROUGH_MIN_MEAN_IOU


def test_tracks_backwards_from_a_later_seed(synthetic_clips):
    """Seeded in frame 30, the tracker covers frames 0–29 too."""
    truth = _truth(synthetic_clips, "calm")
    seed = box_seed_from(MaskTrack.from_array(
        np.stack([truth.mask(t) if t == 30 else np.zeros_like(truth.mask(t))
                  for t in range(truth.num_frames)]), "frame 30 only"))
    iou = measure_tracker(*synthetic_clips["calm"], seed=seed)
    assert seed.frame_idx == 30 and iou[:30].mean() >= CALM_MIN_MEAN_IOU


def test_progress_counts_every_frame(synthetic_clips):
    """Progress comes once per frame, from step 1 of T to T of T, each naming the frame just
    tracked (the seed's, then forwards, then backwards) and what its mask is like."""
    calls, previews = [], []

    def progress(report):
        calls.append((report.stage, report.step, report.total))
        previews.append(report.preview)

    with VideoReader(synthetic_clips["calm"][0]) as frames:
        track = MaskTracker().segment(frames, AutoSeed(10), progress=progress)
    assert calls == [("track", k, 48) for k in range(1, 49)]
    assert [p.frame_idx for p in previews] == [10, *range(11, 48), *range(9, -1, -1)]
    for preview in previews:
        mask = track.mask(preview.frame_idx)
        assert preview.visible == bool(track.is_visible[preview.frame_idx])
        assert preview.touches_border == bool(mask[0].any() or mask[-1].any()
                                              or mask[:, 0].any() or mask[:, -1].any())


def test_cancel_stops_within_a_frame(synthetic_clips):
    """Setting the cancel event from the progress callback stops the tracker at once."""
    cancel = threading.Event()
    calls = []

    def progress(report):
        calls.append(report.step)
        if report.step == 5:
            cancel.set()

    with VideoReader(synthetic_clips["calm"][0]) as frames:
        with pytest.raises(TrackingCancelled) as stopped:
            MaskTracker().segment(frames, AutoSeed(), progress=progress, cancel=cancel)
    assert calls == [1, 2, 3, 4, 5]
    # what it tracked before the cancel is kept: the seed frame and the next four
    assert stopped.value.visited == frozenset(range(5))
    assert stopped.value.track.is_visible.tolist() == [True] * 5 + [False] * 43
    assert isinstance(stopped.value, Cancelled)


def test_seeds_that_find_nothing_raise(synthetic_clips):
    """A click far from the animal and a box outside the frame raise InputError."""
    with VideoReader(synthetic_clips["calm"][0]) as frames:
        with pytest.raises(InputError, match="no dark, elongated animal found at the seed"):
            MaskTracker().segment(frames, PointSeed(300.0, 230.0))
        with pytest.raises(InputError, match="outside the 320x240 px frame"):
            MaskTracker().segment(frames, PointSeed(400.0, 10.0))


class _TruthSegmenter:
    """An 'external segmenter' that returns given masks: the Segmenter interface at work."""

    def __init__(self, masks: MaskTrack) -> None:
        self.masks = masks

    def segment(self, frames, seed, progress=None, cancel=None) -> MaskTrack:
        return self.masks


def test_any_segmenter_can_be_measured(synthetic_clips):
    """measure_tracker takes any Segmenter; the truth itself scores 1 on every frame."""
    truth = _truth(synthetic_clips, "calm-dive")
    iou = measure_tracker(*synthetic_clips["calm-dive"], segmenter=_TruthSegmenter(truth))
    np.testing.assert_array_equal(iou, np.ones(48))


def test_mask_iou():
    """IoU of overlapping squares; two empty masks agree (1), one empty one does not (0)."""
    a = np.zeros((10, 10), bool)
    b = np.zeros((10, 10), bool)
    a[0:4, 0:4] = True
    b[2:6, 2:6] = True
    assert mask_iou(a, b) == 4 / 28
    assert mask_iou(a & False, b & False) == 1.0 and mask_iou(a, b & False) == 0.0


def test_outline_offset_is_the_shift_of_the_outline_in_pixels():
    """Discs of radius 49 and 51 against one of 50: the outline 1 px in and out (within the
    few per cent by which a pixel outline's length exceeds the circle's); none for the same
    mask, NaN where the truth is empty."""
    rows, cols = np.mgrid[:160, :160]
    radius = np.hypot(rows - 80, cols - 80)
    truth = radius <= 50
    assert outline_offset_px(radius <= 51, truth) == pytest.approx(1.0, abs=0.05)
    assert outline_offset_px(radius <= 49, truth) == pytest.approx(-1.0, abs=0.05)
    assert outline_offset_px(truth, truth) == 0.0
    assert np.isnan(outline_offset_px(truth, np.zeros_like(truth)))
