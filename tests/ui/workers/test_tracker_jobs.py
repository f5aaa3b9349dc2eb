"""Tracking jobs (ui/workers/tracker_jobs.py), run directly without Qt on a small synthetic clip: a
dark ellipse moving over blue noise."""

import threading
from pathlib import Path

import cv2
import numpy as np
import pytest
import torch

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import MaskTrack
from dolphinfit.core.progress import Cancelled, Progress
from dolphinfit.core.segment.evaluate import track_iou
from dolphinfit.core.segment.segmenter import PointSeed
from dolphinfit.ui.workers import tracker_jobs
from dolphinfit.ui.workers.tracker_jobs import track_job

NUM_FRAMES, WIDTH, HEIGHT, FPS = 12, 320, 240, 25.0
SEED_FRAME = 6
SEMI_AXES_PX = (45, 14)
WATER_BGR, SKIN_BGR, NOISE_SD = (150, 100, 40), (60, 60, 60), 6.0


def _centre(frame_idx: int) -> tuple[int, int]:
    return 90 + 12 * frame_idx, 100 + 3 * frame_idx


def _true_masks() -> np.ndarray:
    masks = np.zeros((NUM_FRAMES, HEIGHT, WIDTH), np.uint8)
    for t in range(NUM_FRAMES):
        cv2.ellipse(masks[t], _centre(t), SEMI_AXES_PX, 15, 0, 360, 1, -1)
    return masks.astype(bool)


@pytest.fixture(scope="module")
def clip(tmp_path_factory) -> tuple[Path, MaskTrack]:
    """The clip's path and its true masks."""
    path = tmp_path_factory.mktemp("clip") / "ellipse.mp4"
    truth = _true_masks()
    rng = np.random.default_rng(1)
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), FPS, (WIDTH, HEIGHT))
    for mask in truth:
        noise = rng.normal(0.0, NOISE_SD, (HEIGHT, WIDTH, 3))
        frame = np.where(mask[..., None], SKIN_BGR, WATER_BGR) + noise
        writer.write(np.clip(frame, 0, 255).astype(np.uint8))
    writer.release()
    return path, MaskTrack.from_array(truth, "truth")


def test_a_click_tracks_both_ways(clip):
    path, truth = clip
    reports: list[Progress] = []
    centre = _centre(SEED_FRAME)
    job = track_job(path, PointSeed(*centre), SEED_FRAME, "both")
    outcome = job(reports.append, threading.Event())
    track = outcome.track
    assert outcome.complete and outcome.num_tracked == NUM_FRAMES
    assert track.num_frames == NUM_FRAMES
    assert (track_iou(track, truth) > 0.8).all()
    assert [r.step for r in reports] == list(range(1, NUM_FRAMES + 1))
    assert reports[-1].total == NUM_FRAMES
    assert sorted(r.preview.frame_idx for r in reports) == list(range(NUM_FRAMES))
    assert reports[0].preview.frame_idx == SEED_FRAME  # the clip's frame, not the view's


def test_one_direction_keeps_the_other_frames(clip, monkeypatch):
    path, truth = clip
    monkeypatch.setattr(tracker_jobs, "BLOCK_BYTES", 4 * WIDTH * HEIGHT * 3)  # blocks of 4
    existing = MaskTrack.from_array(np.zeros((NUM_FRAMES, HEIGHT, WIDTH), bool), "old")
    backward = track_job(path, PointSeed(*_centre(SEED_FRAME)), SEED_FRAME, "backward",
                         existing)(lambda _: None, threading.Event()).track
    assert backward.is_visible.tolist() == [True] * (SEED_FRAME + 1) + [False] * 5
    assert (track_iou(backward, truth)[:SEED_FRAME + 1] > 0.8).all()
    corrected = truth.mask(SEED_FRAME).copy()
    corrected[:, :_centre(SEED_FRAME)[0] - 38] = False  # the tip erased; the frame keeps it
    assert corrected.sum() < truth.mask(SEED_FRAME).sum()
    both = track_job(path, corrected, SEED_FRAME, "forward", backward)(
        lambda _: None, threading.Event()).track
    assert (track_iou(both, truth) > 0.8).all()
    np.testing.assert_array_equal(both.mask(SEED_FRAME), corrected)
    for t in range(SEED_FRAME):
        np.testing.assert_array_equal(both.mask(t), backward.mask(t))


def test_a_cancel_keeps_the_frames_tracked_and_the_others_masks(clip):
    """Cancelled after the seed frame and two frames forwards (progress step 3): those three
    get their tracked masks, every other frame keeps the mask it had (here the truth shifted
    by 3 px), and the outcome says it is incomplete. A cancel before tracking has begun
    keeps nothing (Cancelled)."""
    path, truth = clip
    existing = MaskTrack.from_array(np.roll([truth.mask(t) for t in range(NUM_FRAMES)], 3,
                                            axis=2), "old")
    cancel = threading.Event()

    def progress(report: Progress) -> None:
        if report.step == 3:
            cancel.set()

    outcome = track_job(path, PointSeed(*_centre(SEED_FRAME)), SEED_FRAME, "both",
                        existing)(progress, cancel)
    assert not outcome.complete and outcome.num_tracked == 3
    reached = {SEED_FRAME, SEED_FRAME + 1, SEED_FRAME + 2}
    iou = track_iou(outcome.track, truth)
    for t in range(NUM_FRAMES):
        if t in reached:
            assert iou[t] > 0.8
        else:
            np.testing.assert_array_equal(outcome.track.mask(t), existing.mask(t))
    cancel.set()
    with pytest.raises(Cancelled):
        track_job(path, PointSeed(*_centre(SEED_FRAME)), SEED_FRAME, "both")(progress, cancel)


def test_a_bad_direction_is_refused(clip):
    with pytest.raises(ValueError, match="direction"):
        track_job(clip[0], PointSeed(1, 1), 0, "sideways")


def test_cuda_where_torch_sees_no_gpu_is_refused_naming_the_setting(clip, monkeypatch):
    """The job resolves the app's compute device before tracking: cuda without a GPU is bad
    input that names where it is chosen."""
    monkeypatch.setattr(torch.cuda, "is_available", lambda: False)
    job = track_job(clip[0], PointSeed(*_centre(SEED_FRAME)), SEED_FRAME, "both",
                    device="cuda")
    with pytest.raises(InputError, match="^Edit → Compute device cuda: .*no CUDA GPU"):
        job(lambda report: None, threading.Event())


def test_a_back_end_limited_to_some_frames_keeps_the_others_masks(clip):
    """Tracking only the frames a fit uses (SAM-2 in the app) replaces those frames' masks
    and the seed frame's, and leaves every other frame's mask as it was (a correction made
    there is not blanked)."""
    path, truth = clip
    existing = MaskTrack.from_array(np.roll([truth.mask(t) for t in range(NUM_FRAMES)], 3,
                                            axis=2), "old")
    chosen = [2, 8, 10]
    track = track_job(path, PointSeed(*_centre(SEED_FRAME)), SEED_FRAME, "both", existing,
                      only_frames=np.array(chosen))(lambda _: None, threading.Event()).track
    segmented = {*chosen, SEED_FRAME}
    for t in range(NUM_FRAMES):
        if t in segmented:
            assert track_iou(track, truth)[t] > 0.8
        else:
            np.testing.assert_array_equal(track.mask(t), existing.mask(t))
