"""The SAM-2 back-end: its checks, the frame folder it writes and, where the ``sam2`` package
and a checkpoint ($DOLPHINFIT_SAM2_CHECKPOINT) are installed, SAM-2 itself on a synthetic
clip. Nothing stands in for the model: what needs it is skipped without it."""

import importlib.util
import os
import re
import subprocess
import sys
import threading
from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import read_png_folder
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.progress import Cancelled
from dolphinfit.core.segment.backends import SAM2, make_segmenter
from dolphinfit.core.segment.sam2_backend import (
    JPEG_NAME,
    Sam2Segmenter,
    check_checkpoint,
    chosen_frames,
    config_for,
    prompt,
    write_jpeg_folder,
)
from dolphinfit.core.segment.segmenter import AutoSeed, BoxSeed, PointSeed

HAS_SAM2 = importlib.util.find_spec("sam2") is not None
CHECKPOINT = os.environ.get("DOLPHINFIT_SAM2_CHECKPOINT")
needs_sam2 = pytest.mark.skipif(not HAS_SAM2, reason="the sam2 package is not installed")
needs_model = pytest.mark.skipif(
    not (HAS_SAM2 and CHECKPOINT),
    reason="needs the sam2 package and a checkpoint named by $DOLPHINFIT_SAM2_CHECKPOINT")


@pytest.fixture
def tiny_checkpoint(tmp_path) -> Path:
    """A file with an official checkpoint's name: enough for every check before loading."""
    path = tmp_path / "sam2.1_hiera_tiny.pt"
    path.write_bytes(b"")
    return path


@pytest.mark.parametrize("name, config", [
    ("sam2.1_hiera_tiny.pt", "configs/sam2.1/sam2.1_hiera_t.yaml"),
    ("sam2.1_hiera_small.pt", "configs/sam2.1/sam2.1_hiera_s.yaml"),
    ("sam2.1_hiera_base_plus.pt", "configs/sam2.1/sam2.1_hiera_b+.yaml"),
    ("sam2.1_hiera_large.pt", "configs/sam2.1/sam2.1_hiera_l.yaml"),
    ("sam2_hiera_tiny.pt", "configs/sam2/sam2_hiera_t.yaml"),
    ("sam2_hiera_large.pt", "configs/sam2/sam2_hiera_l.yaml"),
])
def test_model_configuration_from_the_official_checkpoint_names(name, config):
    assert config_for(Path("/models") / name) == config


@pytest.mark.parametrize("name, problem", [
    ("model.pt", "cannot tell the SAM-2 model from the file name 'model.pt'"),
    ("sam2.1_hiera_huge.pt", "unknown SAM-2 model size 'huge'"),
    ("sam3_hiera_tiny.pt", "cannot tell the SAM-2 model"),
])
def test_checkpoint_names_that_name_no_official_model_are_refused(name, problem):
    with pytest.raises(InputError, match=problem):
        config_for(Path(name))


def test_checkpoint_must_be_an_existing_pt_file(tmp_path, tiny_checkpoint):
    assert check_checkpoint(str(tiny_checkpoint)) == tiny_checkpoint
    with pytest.raises(InputError, match=re.escape(f"{tmp_path / 'gone.pt'}: no such file")):
        check_checkpoint(tmp_path / "gone.pt")
    with pytest.raises(InputError, match=re.escape(f"{tmp_path}: not a file")):
        check_checkpoint(tmp_path)
    text = tmp_path / "sam2.1_hiera_tiny.txt"
    text.write_text("not a checkpoint")
    with pytest.raises(InputError, match=r"sam2.1_hiera_tiny.txt: not a SAM-2 checkpoint \("
                                         r"expected a .pt file"):
        check_checkpoint(text)


def test_sam2_needs_a_checkpoint():
    with pytest.raises(InputError, match="'sam2': needs a SAM-2 checkpoint file"):
        make_segmenter(SAM2)


@pytest.mark.skipif(HAS_SAM2, reason="the sam2 package is installed here")
def test_without_the_package_the_error_says_how_to_install_it(tiny_checkpoint):
    with pytest.raises(InputError, match=r"needs the 'sam2' package, which is not installed; "
                                         r"install it yourself .*SAM2_BUILD_CUDA=0 pip install"
                                         r" -e \..*torchvision"):
        make_segmenter(SAM2, checkpoint=tiny_checkpoint)


@needs_sam2
def test_auto_seed_is_refused(tiny_checkpoint):
    segmenter = Sam2Segmenter(tiny_checkpoint)
    assert segmenter.config == "configs/sam2.1/sam2.1_hiera_t.yaml"
    with pytest.raises(InputError, match="SAM-2 needs a click or a box"):
        segmenter.segment([np.zeros((8, 8, 3), np.uint8)], AutoSeed())


def test_importing_the_back_ends_loads_no_sam2():
    """sam2 (and what it pulls in) is imported only when a model is built."""
    probe = ("import sys, core.segment.backends, core.segment.sam2_backend\n"
             "print(sorted({m.split('.')[0] for m in sys.modules} & "
             "{'sam2', 'hydra', 'omegaconf', 'torchvision'}))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


def test_chosen_frames_map_local_frames_to_the_clip_in_time_order():
    chosen = chosen_frames(10, 5, [8, 0, 4, 12, -1, 4])
    assert chosen == [0, 4, 5, 8]  # in the clip, the seed added, sorted, once each
    assert chosen.index(5) == 2    # the seed's local frame
    assert chosen_frames(4, 2, None) == [0, 1, 2, 3]
    assert chosen_frames(10, 3, range(0, 10, 4)) == [0, 3, 4, 8]
    assert chosen_frames(10, 3, np.arange(0, 10, 4)) == [0, 3, 4, 8]  # as the fit's frames


def test_the_frame_folder_holds_the_chosen_frames_in_order(tmp_path):
    """Local frame i is clip frame chosen[i], as SAM-2 reads the folder (by integer name)."""
    ramp = np.linspace(0, 30, 32)[None, :, None]  # smooth frames, red ≠ blue, one per level
    frames = [np.broadcast_to(ramp + [30 + 20 * t, 100, 210 - 15 * t], (24, 32, 3))
              .astype(np.uint8) for t in range(10)]
    chosen = [0, 4, 5, 8]
    assert write_jpeg_folder(frames, chosen, tmp_path) == (24, 32)
    names = sorted((p.name for p in tmp_path.iterdir()), key=lambda n: int(Path(n).stem))
    assert names == [JPEG_NAME.format(i) for i in range(len(chosen))]
    for local_idx, frame_idx in enumerate(chosen):
        rgb = cv2.cvtColor(cv2.imread(str(tmp_path / names[local_idx])), cv2.COLOR_BGR2RGB)
        assert np.abs(rgb.astype(float) - frames[frame_idx]).mean() < 3


def test_prompts_are_a_positive_click_or_a_corner_box():
    assert prompt(PointSeed(12.5, 40.0, 3)) == {"points": [[12.5, 40.0]], "labels": [1]}
    assert prompt(BoxSeed(10, 20, 30, 5, 3)) == {"box": [10, 20, 40, 25]}


@needs_model
def test_sam2_tracks_the_synthetic_animal_on_the_chosen_frames(synthetic_clips):
    """From a click in frame 16, both ways, every 8th frame: the chosen frames match the truth,
    the others are not visible, progress counts each chosen frame once."""
    clip_path, masks_dir = synthetic_clips["calm"]
    clip = open_clip(clip_path)
    truth = read_png_folder(masks_dir, clip)
    only = list(range(0, clip.num_frames, 8))
    inside = cv2.distanceTransform(truth.mask(16).astype(np.uint8), cv2.DIST_L2, 3)
    y_px, x_px = np.unravel_index(np.argmax(inside), inside.shape)  # deep inside the body
    seed = PointSeed(float(x_px), float(y_px), 16)
    reports = []
    with VideoReader(clip) as frames:
        track = Sam2Segmenter(CHECKPOINT, only_frames=only).segment(frames, seed, reports.append)
    assert "SAM-2" in track.source and Path(CHECKPOINT).name in track.source
    assert set(np.flatnonzero(track.is_visible)) <= set(only)
    assert [r.step for r in reports] == list(range(1, len(only) + 1))
    assert all(r.total == len(only) for r in reports)
    ious = [mask_iou(track.mask(t), truth.mask(t)) for t in only]
    assert min(ious) > 0.7, ious


@needs_model
def test_sam2_stops_when_cancelled(synthetic_clips):
    clip_path, _ = synthetic_clips["calm"]
    cancel = threading.Event()
    reports = []

    def cancel_after_first(report):
        reports.append(report)
        cancel.set()

    with VideoReader(open_clip(clip_path)) as frames, pytest.raises(Cancelled):
        Sam2Segmenter(CHECKPOINT, only_frames=[0, 8, 16]).segment(
            frames, PointSeed(100.0, 100.0, 0), cancel_after_first, cancel)
    assert len(reports) == 1
