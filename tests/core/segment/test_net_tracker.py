"""The network tracker on the synthetic tracker clips (conftest.py), with the installed weights.

The network runs on every 8th frame only (as it does for a fit), which keeps each clip to
a handful of network calls.
"""

import threading
from dataclasses import replace

import cv2
import numpy as np
import pytest

from core.errors import InputError
from core.io.masks import read_png_folder
from core.io.video import VideoReader, open_clip
from core.iou import mask_iou
from core.progress import Cancelled
from core.segment.backends import make_segmenter
from core.segment.evaluate import box_seed_from
from core.segment.net_tracker import BACKEND_NAME, NetTracker, square_window
from core.segment.salient import SalientNet
from core.segment.segmenter import AutoSeed, PointSeed
from core.segment.weights import U2NETP

STRIDE = 8


@pytest.fixture(scope="module")
def net() -> SalientNet:
    return SalientNet()


def _run(clip_and_truth, net, seed=None, only=None, **kwargs):
    clip_path, masks_dir = clip_and_truth
    clip = open_clip(clip_path)
    truth = read_png_folder(masks_dir, clip)
    only = list(range(0, truth.num_frames, STRIDE)) if only is None else only
    with VideoReader(clip) as frames:
        track = NetTracker(only_frames=only, net=net).segment(
            frames, seed or box_seed_from(truth), **kwargs)
    return track, truth, only


def _ious(track, truth, frames) -> np.ndarray:
    return np.array([mask_iou(track.mask(t), truth.mask(t)) for t in frames])


def test_saliency_is_high_on_an_animal_and_low_on_water(net):
    """A grey elongated body on flat green water: the network marks the body, not the water."""
    crop = np.full((200, 200, 3), (40, 110, 90), np.uint8)
    cv2.ellipse(crop, (100, 100), (70, 14), 30, 0, 360, (170, 170, 165), -1)
    body = np.zeros((200, 200), np.uint8)
    cv2.ellipse(body, (100, 100), (70, 14), 30, 0, 360, 1, -1)
    saliency = net.saliency(crop)
    assert saliency.shape == (200, 200)
    assert saliency[body == 1].mean() > 0.8
    assert saliency[cv2.dilate(body, np.ones((15, 15))) == 0].mean() < 0.1
    assert mask_iou(saliency >= 0.5, body == 1) > 0.85


@pytest.mark.parametrize("kind", ["calm", "rough"])
def test_box_seed_meets_the_aim(synthetic_clips, net, kind):
    """Mean IoU ≥ 0.9 on calm water and on rough water with waves and glints (0.93 measured
    on both)."""
    track, truth, only = _run(synthetic_clips[kind], net)
    assert _ious(track, truth, only).mean() >= 0.9
    assert track.source.startswith(BACKEND_NAME)


def test_only_the_chosen_frames_are_segmented_and_counted(synthetic_clips, net):
    reports = []
    track, truth, only = _run(synthetic_clips["calm"], net, only=[0, 10, 20],
                              seed=None, progress=reports.append)
    assert list(np.flatnonzero(track.is_visible)) == [0, 10, 20]
    assert [(r.step, r.total) for r in reports] == [(1, 3), (2, 3), (3, 3)]


def test_dive_is_lost_and_found_again(synthetic_clips, net):
    """Frames 28–36 are under water (no true mask): none is reported; frames from 42 on,
    back at the surface, are found again."""
    track, truth, only = _run(synthetic_clips["rough-dive"], net, only=[0, 8, 16, 30, 36, 42])
    assert not track.is_visible[[30, 36]].any()
    assert _ious(track, truth, [42]).min() >= 0.85
    assert _ious(track, truth, [0, 8, 16]).mean() >= 0.9


def test_automatic_and_point_seeds_find_the_animal(synthetic_clips, net):
    clip_path, masks_dir = synthetic_clips["calm"]
    truth = read_png_folder(masks_dir, open_clip(clip_path))
    rows, cols = np.nonzero(truth.mask(0))
    for seed in (AutoSeed(0), PointSeed(float(cols.mean()), float(rows.mean()), 0)):
        track, _, _ = _run(synthetic_clips["calm"], net, seed=seed, only=[0])
        assert mask_iou(track.mask(0), truth.mask(0)) >= 0.9


def test_a_click_outside_the_frame_is_refused(synthetic_clips, net):
    with pytest.raises(InputError, match="outside"):
        _run(synthetic_clips["calm"], net, seed=PointSeed(-5.0, 10.0, 0), only=[0])


def test_cancel_stops_before_the_next_frame(synthetic_clips, net):
    cancel = threading.Event()
    with pytest.raises(Cancelled):
        _run(synthetic_clips["calm"], net, progress=lambda report: cancel.set(),
             cancel=cancel)


def test_square_windows_stay_inside_the_frame():
    rows, cols = square_window(np.array([5.0, 230.0]), 100, 240, 320)
    assert (rows, cols) == (slice(140, 240), slice(0, 100))
    rows, cols = square_window(np.array([160.0, 120.0]), 500, 240, 320)
    assert (rows.stop - rows.start, cols.stop - cols.start) == (240, 240)


def test_missing_or_altered_weights_say_how_to_install(tmp_path, monkeypatch):
    monkeypatch.setattr("core.segment.weights.MODELS_DIR", tmp_path)
    with pytest.raises(InputError, match="python -m core.segment.weights"):
        SalientNet(U2NETP)
    (tmp_path / U2NETP.file_name).write_bytes(b"not the network")
    with pytest.raises(InputError, match="altered"):
        SalientNet(U2NETP)
    with pytest.raises(InputError, match="installed"):
        SalientNet(replace(U2NETP, file_name="other.onnx"))


def test_back_ends_by_name():
    assert isinstance(make_segmenter("network", only_frames=[0]), NetTracker)
    assert type(make_segmenter("colour")).__name__ == "MaskTracker"
    with pytest.raises(InputError, match="unknown; choose one of network, colour"):
        make_segmenter("sam")
