"""The loop every tracker shares: from the seed frame forwards over the chosen frames, then
backwards, each pass from the seed's mask with a fresh state; and the MaskTrack of what it
found, also when it is cancelled (TrackingCancelled). A tracker brings only its step from one
frame to the next."""

import threading
from collections.abc import Callable, Sequence
from typing import TypeVar

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import MaskTrack
from dolphinfit.core.progress import Cancelled, Progress, ProgressCallback, check_cancel
from dolphinfit.core.segment.regions import MaskCrop, crop_of, touches_border
from dolphinfit.core.segment.segmenter import (
    TRACK_STAGE, BoxSeed, FrameTracked, Frames, PointSeed, Seed, TrackingCancelled,
)

State = TypeVar("State")


def check_seed_frame(seed: Seed, num_frames: int) -> None:
    """IndexError unless the seed's frame lies in the clip."""
    if not 0 <= seed.frame_idx < num_frames:
        raise IndexError(f"seed frame {seed.frame_idx} is outside the clip "
                         f"(0…{num_frames - 1})")


def check_seed_inside(seed: Seed, width_px: int, height_px: int) -> None:
    """InputError unless a click lies in the frame and a box wholly inside it (an automatic
    seed has no place)."""
    frame = f"the {width_px}×{height_px} frame"
    if isinstance(seed, PointSeed) and not (0 <= seed.x_px < width_px
                                            and 0 <= seed.y_px < height_px):
        raise InputError(f"the click ({seed.x_px:g}, {seed.y_px:g}) lies outside {frame}")
    if isinstance(seed, BoxSeed) and not (
            0 <= seed.x_px and 0 <= seed.y_px and seed.x_px + seed.width_px <= width_px
            and seed.y_px + seed.height_px <= height_px):
        raise InputError(f"the box at ({seed.x_px}, {seed.y_px}), {seed.width_px}×"
                         f"{seed.height_px} px, is not wholly inside {frame}")


def track_both_ways(frames: Frames, seed_idx: int, seed_mask: np.ndarray,
                    chosen: Sequence[int], start: Callable[[], State],
                    step: Callable[[np.ndarray, State], np.ndarray | None],
                    finish: Callable[[dict[int, MaskCrop]], MaskTrack],
                    progress: ProgressCallback | None = None,
                    cancel: threading.Event | None = None) -> MaskTrack:
    """``finish`` of the animal's crops in the seed frame and the ``chosen`` frames:
    ``step(frame, state)`` gives each frame's mask (None: not seen) from the state
    ``start()`` makes afresh for the pass forwards from the seed, then for the pass
    backwards. Each progress report's preview is the FrameTracked just done. Once ``cancel``
    is set, TrackingCancelled with ``finish`` of the crops so far."""
    forward = [t for t in chosen if t > seed_idx]
    backward = [t for t in reversed(chosen) if t < seed_idx]
    total = 1 + len(forward) + len(backward)
    crops, visited = {}, []

    def keep(frame_idx: int, found: np.ndarray | None) -> None:
        if found is not None:
            crops[frame_idx] = crop_of(found)
        visited.append(frame_idx)
        if progress is not None:
            progress(Progress(TRACK_STAGE, len(visited), total, preview=FrameTracked(
                frame_idx, found is not None, found is not None and touches_border(found))))

    keep(seed_idx, seed_mask)
    try:
        for order in (forward, backward):
            state = start()
            for frame_idx in order:
                check_cancel(cancel)
                keep(frame_idx, step(frames[frame_idx], state))
    except Cancelled:
        raise TrackingCancelled(finish(crops), frozenset(visited)) from None
    return finish(crops)


def track_of(crops: dict[int, MaskCrop], num_frames: int, width: int, height: int,
             source: str, paste: Callable[[MaskCrop], np.ndarray] | None = None) -> MaskTrack:
    """The MaskTrack of the frames that have a crop; ``paste`` turns a crop into its frame's
    (height, width) mask (default: pasted at that size)."""
    is_visible = np.array([t in crops for t in range(num_frames)])
    pasted = paste if paste is not None else (lambda crop: crop.paste(height, width))
    return MaskTrack(is_visible, width, height, source, lambda t: pasted(crops[t]))
