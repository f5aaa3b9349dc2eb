"""SAM-2 (the paper's segmenter) as an optional mask back-end, for users who have it.

SAM-2's video predictor (the ``sam2`` package of facebookresearch/sam2) tracks one object from
a click or a box through a folder of JPEG frames named by their index. Neither the package
(which needs torchvision built for the installed torch) nor a checkpoint comes with
dolphinfit: the user installs and downloads them and names the checkpoint; the model's
configuration follows from the checkpoint's official file name (``sam2.1_hiera_tiny.pt`` →
``configs/sam2.1/sam2.1_hiera_t.yaml``).

It runs on the CPU unless given a CUDA device (core.device); on the CPU it is slow, so it
sees only the chosen frames (those a fit uses) and the seed frame: they are written in time
order as local frames 0…n−1, the predictor is prompted on the seed's local frame and
propagates forwards to the last and backwards to the first, and each local frame's mask goes
back to its clip frame. Frames not chosen, and chosen
frames where SAM-2 marks nothing, are not visible. ``sam2`` is imported only when a model is
built, so importing this module needs neither it nor torchvision.
"""

import importlib.util
import re
import tempfile
import threading
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import cv2
import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import MaskTrack
from dolphinfit.core.progress import Cancelled, Progress, ProgressCallback, check_cancel
from dolphinfit.core.segment.regions import MaskCrop, crop_of, touches_border
from dolphinfit.core.segment.segmenter import (
    TRACK_STAGE, AutoSeed, BoxSeed, Frames, FrameTracked, PointSeed, Seed, TrackingCancelled,
)
from dolphinfit.core.segment.tracking_loop import check_seed_frame, track_of

if TYPE_CHECKING:
    import torch

PACKAGE = "sam2"
INSTALL_HINT = ("install it yourself (dolphinfit does not): clone "
                "https://github.com/facebookresearch/sam2 and run "
                "'SAM2_BUILD_CUDA=0 pip install -e .' in it; it needs torchvision built for "
                "the installed torch")
CHECKPOINT_SUFFIX = ".pt"
# sam2_hiera_<size>.pt and sam2.1_hiera_<size>.pt → configs/<version>/<version>_hiera_<s>.yaml
CHECKPOINT_NAME = re.compile(r"^(sam2(?:\.1)?)_hiera_(.+)$")
SIZES = {"tiny": "t", "small": "s", "base_plus": "b+", "large": "l"}
JPEG_NAME = "{:06d}.jpg"  # the predictor orders a folder's frames by the integer name
JPEG_QUALITY = 95
OBJECT_ID = 1
POSITIVE = 1  # SAM-2's label of a click on the object


def check_checkpoint(path: Path | str) -> Path:
    """``path`` as a Path if it is an existing ``.pt`` file; InputError naming it otherwise."""
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such file (a SAM-2 checkpoint, e.g. "
                         "sam2.1_hiera_tiny.pt)")
    if not path.is_file():
        raise InputError(f"{path}: not a file (a SAM-2 checkpoint, e.g. sam2.1_hiera_tiny.pt)")
    if path.suffix.lower() != CHECKPOINT_SUFFIX:
        raise InputError(f"{path}: not a SAM-2 checkpoint (expected a {CHECKPOINT_SUFFIX} "
                         "file, e.g. sam2.1_hiera_tiny.pt)")
    return path


def config_for(checkpoint: Path | str) -> str:
    """The model configuration of an official checkpoint, from its file name; InputError when
    the name is not one of the official ones."""
    name = Path(checkpoint).name
    match = CHECKPOINT_NAME.match(Path(checkpoint).stem)
    if match is None:
        raise InputError(f"{checkpoint}: cannot tell the SAM-2 model from the file name "
                         f"{name!r}; keep the official name, e.g. sam2.1_hiera_tiny.pt")
    version, size = match.groups()
    if size not in SIZES:
        raise InputError(f"{checkpoint}: unknown SAM-2 model size {size!r} in {name!r}; "
                         f"one of {', '.join(SIZES)}")
    return f"configs/{version}/{version}_hiera_{SIZES[size]}.yaml"


def installed() -> bool:
    """Whether the ``sam2`` package can be found (it is not imported)."""
    return importlib.util.find_spec(PACKAGE) is not None


def check_installed() -> None:
    """InputError with the install hint when the ``sam2`` package is absent."""
    if not installed():
        raise InputError(f"the mask back-end SAM-2 needs the '{PACKAGE}' package, which is not "
                         f"installed; {INSTALL_HINT}")


def chosen_frames(num_frames: int, seed_frame: int,
                  only_frames: Sequence[int] | None) -> list[int]:
    """The clip frames SAM-2 sees, in time order (local frame i is clip frame ``[i]``): those
    of ``only_frames`` inside the clip (every frame when None) and the seed frame."""
    wanted = range(num_frames) if only_frames is None else only_frames
    return sorted({int(t) for t in wanted if 0 <= t < num_frames} | {seed_frame})


def write_jpeg_folder(frames: Frames, chosen: Sequence[int], folder: Path) -> tuple[int, int]:
    """Clip frames ``chosen`` (RGB) as ``folder/%06d.jpg`` numbered 0…n−1 in that order; the
    frames' (height, width)."""
    for local_idx, frame_idx in enumerate(chosen):
        path = folder / JPEG_NAME.format(local_idx)
        frame = frames[frame_idx]
        bgr = cv2.cvtColor(frame, cv2.COLOR_RGB2BGR)
        if not cv2.imwrite(str(path), bgr, [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY]):
            raise OSError(f"{path}: cannot be written")
    return frame.shape[0], frame.shape[1]


def prompt(seed: PointSeed | BoxSeed) -> dict[str, list]:
    """The predictor's prompt for a seed: a positive point, or a box as (x0, y0, x1, y1)."""
    if isinstance(seed, BoxSeed):
        return {"box": [seed.x_px, seed.y_px, seed.x_px + seed.width_px,
                        seed.y_px + seed.height_px]}
    return {"points": [[seed.x_px, seed.y_px]], "labels": [POSITIVE]}


class Sam2Segmenter:
    """SAM-2's video predictor as a ``Segmenter`` (module doc)."""

    def __init__(self, checkpoint: Path | str, only_frames: Sequence[int] | None = None,
                 config: str | None = None, device: "torch.device | str" = "cpu") -> None:
        """``checkpoint``: a SAM-2 ``.pt`` file; ``config``: its model configuration (default:
        from the official file name); ``only_frames``: segment just these frame indices (the
        seed frame always); ``device``: where the model runs. InputError for a bad
        checkpoint or without the package."""
        self.checkpoint = check_checkpoint(checkpoint)
        self.config = config_for(self.checkpoint) if config is None else config
        check_installed()
        self.only_frames = only_frames
        self.device = device
        self._predictor = None

    def segment(self, frames: Frames, seed: Seed, progress: ProgressCallback | None = None,
                cancel: threading.Event | None = None) -> MaskTrack:
        """Masks for the chosen frames of ``frames``, propagated from ``seed``.

        InputError for an AutoSeed (SAM-2 needs a click or a box) or a checkpoint the model
        cannot load; core.progress.Cancelled once ``cancel`` is set.
        """
        if isinstance(seed, AutoSeed):
            raise InputError("SAM-2 needs a click or a box on the animal; it does not find "
                             "one by itself")
        num_frames = len(frames)
        check_seed_frame(seed, num_frames)
        chosen = chosen_frames(num_frames, seed.frame_idx, self.only_frames)
        seed_local = chosen.index(seed.frame_idx)
        check_cancel(cancel)
        predictor = self._load()
        crops: dict[int, MaskCrop] = {}
        with tempfile.TemporaryDirectory(prefix="dolphinfit-sam2-") as folder:
            height, width = write_jpeg_folder(frames, chosen, Path(folder))
            check_cancel(cancel)
            state = predictor.init_state(video_path=folder, offload_video_to_cpu=True)
            predictor.add_new_points_or_box(state, frame_idx=seed_local, obj_id=OBJECT_ID,
                                            **prompt(seed))
            source, visited = f"SAM-2 ({self.checkpoint.name}) from {seed}", set()
            try:
                for local_idx, mask in _propagate(predictor, state, seed_local):
                    visited.add(chosen[local_idx])
                    if mask.any():
                        crops[chosen[local_idx]] = crop_of(mask)
                    if progress is not None:
                        progress(Progress(TRACK_STAGE, len(visited), len(chosen),
                                          preview=FrameTracked(chosen[local_idx], mask.any(),
                                                               touches_border(mask))))
                    check_cancel(cancel)
            except Cancelled:
                raise TrackingCancelled(track_of(crops, num_frames, width, height, source),
                                        frozenset(visited)) from None
        return track_of(crops, num_frames, width, height, source)

    def _load(self):
        """The video predictor on the segmenter's device, built once."""
        if self._predictor is None:
            try:
                from sam2.build_sam import build_sam2_video_predictor
            except ImportError as exc:
                raise InputError(f"the '{PACKAGE}' package is installed but cannot be "
                                 f"imported ({exc}); {INSTALL_HINT}") from exc
            try:
                self._predictor = build_sam2_video_predictor(self.config, str(self.checkpoint),
                                                             device=self.device)
            except Exception as exc:  # sam2/hydra/torch errors: the file or config is wrong
                raise InputError(f"{self.checkpoint}: SAM-2 cannot load it with the model "
                                 f"configuration {self.config} ({type(exc).__name__}: "
                                 f"{exc})") from exc
        return self._predictor


def _propagate(predictor, state: dict, seed_local: int) -> Iterator[tuple[int, np.ndarray]]:
    """(local frame, (H, W) bool mask) from the seed forwards to the last frame, then from the
    seed backwards to the first; the seed frame once (both passes start with it)."""
    for reverse in (False, True):
        for local_idx, _, logits in predictor.propagate_in_video(
                state, start_frame_idx=seed_local, reverse=reverse):
            if not (reverse and local_idx == seed_local):
                yield local_idx, (logits[0, 0] > 0).cpu().numpy()
