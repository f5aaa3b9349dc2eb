"""Tracking a large animal at a working scale.

The networks learnt dolphins a few hundred pixels long; a whale close to the drone is
thousands, longer than the frame is high. Such an animal is tracked in frames downscaled
until it is at most ``max_length_px`` long (``NetSettings``), and its masks are brought back to
the frame's size: an outline one working pixel off is then a small share of a large body.
"""

import cv2
import numpy as np

from dolphinfit.core.segment.segmenter import AutoSeed, BoxSeed, Frames, PointSeed, Seed


class ScaledFrames:
    """``frames`` downscaled by ``scale`` (< 1), one frame at a time as they are asked for."""

    def __init__(self, frames: Frames, scale: float, height_px: int, width_px: int) -> None:
        self.frames, self.scale = frames, scale
        self.size = scaled_size(height_px, width_px, scale)

    def __len__(self) -> int:
        return len(self.frames)

    def __getitem__(self, frame_idx: int) -> np.ndarray:
        return resized(self.frames[frame_idx], self.size)


def scaled_size(height_px: int, width_px: int, scale: float) -> tuple[int, int]:
    """(height, width) of a frame downscaled by ``scale``, at least one pixel."""
    return max(1, round(height_px * scale)), max(1, round(width_px * scale))


def resized(frame_rgb: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """The frame at (height, width) ``size``, averaged over the pixels each one covers."""
    return cv2.resize(frame_rgb, (size[1], size[0]), interpolation=cv2.INTER_AREA)


def scaled_seed(seed: Seed, scale: float) -> Seed:
    """The seed in frames downscaled by ``scale`` (pixel centres map to pixel centres)."""
    if isinstance(seed, PointSeed):
        return PointSeed((seed.x_px + 0.5) * scale - 0.5, (seed.y_px + 0.5) * scale - 0.5,
                         seed.frame_idx)
    if isinstance(seed, BoxSeed):
        return BoxSeed(int(seed.x_px * scale), int(seed.y_px * scale),
                       max(1, round(seed.width_px * scale)),
                       max(1, round(seed.height_px * scale)), seed.frame_idx)
    return AutoSeed(seed.frame_idx, None if seed.length_px is None else
                    (seed.length_px[0] * scale, seed.length_px[1] * scale))


def downscaled(mask: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """A frame-sized bool mask at a working scale's (height, width) ``size``: the pixels it
    covers at least half of."""
    return resized(mask.astype(np.float32), size) >= 0.5


def upscaled(mask: np.ndarray, height_px: int, width_px: int) -> np.ndarray:
    """A working-scale bool mask at the frame's (height, width), its outline interpolated
    between the working pixels rather than stepped."""
    grey = cv2.resize(mask.astype(np.float32), (width_px, height_px),
                      interpolation=cv2.INTER_LINEAR)
    return grey >= 0.5
