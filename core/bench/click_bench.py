"""How long a user waits after a click (``dolphinfit bench app``): on the 10-s 1080p speed clip
(25 fps), the default mask back-end from a click on the target in the frame nearest the
clip's middle, as the app tracks after a click (ui/controllers/mask_controller.py): the
clicked frame alone first, then the frames a default fit uses from that frame's mask. Seconds
from opening the clip to the clicked frame's mask, and to the masks of every frame the fit
uses; their IoU against the true masks."""

import time

import numpy as np

from dolphinfit.core.bench.fit_bench import SPEED_CACHE, SPEED_CLIP
from dolphinfit.core.bench.mask_bench import target_clicks
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.segment.backends import DEFAULT_BACKEND, make_segmenter
from dolphinfit.core.segment.segmenter import BoxSeed, PointSeed
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.sample import cache_dir, ensure_clip

AIMS_S = {"first_mask_s": 3.0, "fit_masks_s": 15.0}   # issue 28, two cores


def middle_click(truth: dict) -> PointSeed:
    """The click on the target in the visible frame nearest the clip's middle."""
    clicks = target_clicks(truth)
    if not clicks:
        raise ValueError("the clip's target is never visible")
    middle = len(truth["frames"]) / 2
    return min(clicks, key=lambda click: abs(click.frame_idx - middle))


def bench_click(clip: SynthConfig = SPEED_CLIP, backend: str = DEFAULT_BACKEND) -> dict:
    """Seconds to the clicked frame's mask and to the fit's frames' masks (module doc)."""
    files = ensure_clip(clip, cache_dir() / SPEED_CACHE / "speed")
    seed = middle_click(read_json(files.truth_json, "the clip's truth"))
    start = time.perf_counter()  # as in the app: the clip opened, the back-end made, tracked
    media = open_clip(files.video)
    chosen = sorted({*FitConfig().frames_of(media).tolist(), seed.frame_idx})
    with VideoReader(media, cache_bytes=0) as frames:
        first = make_segmenter(backend, only_frames=[seed.frame_idx]).segment(frames, seed)
        first_s = time.perf_counter() - start
        kept = first.mask(seed.frame_idx)
        track = make_segmenter(backend, only_frames=chosen).segment(
            frames, BoxSeed.around(kept, seed.frame_idx))
    total = time.perf_counter() - start
    truth = read_masks(files.masks_dir, media)
    iou = [float(mask_iou(kept if t == seed.frame_idx else track.mask(t), truth.mask(t)))
           for t in chosen]
    return {"backend": backend, "video_s": clip.duration_s, "clip_fps": clip.fps,
            "width_px": clip.width_px, "height_px": clip.height_px,
            "clicked_frame": seed.frame_idx, "fit_frames": len(chosen),
            "first_mask_s": first_s, "fit_masks_s": total, "mean_iou": float(np.mean(iou)),
            "worst_iou": float(np.min(iou)), "aims_s": AIMS_S}
