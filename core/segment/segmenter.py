"""The segmenter interface: frames in, per-frame masks and visibility flags out.

The built-in tracker implements it; so can a wrapper around an external model. Frames are any
sequence of (H, W, 3) uint8 RGB arrays with a length (a ``VideoReader``, a list). A segmenter
reports ``Progress(TRACK_STAGE, frames done, frames in all)`` after each frame and checks
``cancel`` before each frame (the contract of core.progress).
"""

import threading
from dataclasses import dataclass
from typing import Protocol

import cv2
import numpy as np

from dolphinfit.core.io.masks import MaskTrack
from dolphinfit.core.progress import Cancelled, ProgressCallback

TRACK_STAGE = "track"


class Frames(Protocol):
    """A sequence of (H, W, 3) uint8 RGB frames."""

    def __len__(self) -> int: ...

    def __getitem__(self, frame_idx: int) -> np.ndarray: ...


@dataclass(frozen=True)
class PointSeed:
    """A click on the animal in frame ``frame_idx``, pixels."""

    x_px: float
    y_px: float
    frame_idx: int = 0


@dataclass(frozen=True)
class BoxSeed:
    """A box around the animal in frame ``frame_idx``: top-left corner and size, pixels."""

    x_px: int
    y_px: int
    width_px: int
    height_px: int
    frame_idx: int = 0

    @classmethod
    def around(cls, mask: np.ndarray, frame_idx: int) -> "BoxSeed":
        """The box around an (H, W) mask's pixels; ValueError if it is empty."""
        if not mask.any():
            raise ValueError(f"frame {frame_idx}: the mask is empty, nothing to track from")
        x_px, y_px, width_px, height_px = cv2.boundingRect(mask.astype(np.uint8))
        return cls(x_px, y_px, width_px, height_px, frame_idx)


@dataclass(frozen=True)
class AutoSeed:
    """Find the animal by itself, in frame ``frame_idx`` or, where it is not seen there, in
    later or earlier frames. ``length_px``: the (shortest, longest) length in pixels an
    animal can have in the clip, where the camera and altitude say (``expected_length_px``);
    None: any."""

    frame_idx: int = 0
    length_px: tuple[float, float] | None = None


Seed = PointSeed | BoxSeed | AutoSeed


@dataclass(frozen=True)
class FrameTracked:
    """The preview of a tracking progress report: the frame just tracked, whether the animal
    was seen there, and whether its mask touches the frame's border (a coverage strip fills
    as frames arrive)."""

    frame_idx: int
    visible: bool
    touches_border: bool


class TrackingCancelled(Cancelled):
    """Tracking stopped by the caller after it had tracked some frames: ``track`` holds their
    masks (the frames it had not reached are not visible), ``visited`` which frames it had
    reached (the animal may be lost in some of them)."""

    def __init__(self, track: MaskTrack, visited: frozenset[int]) -> None:
        super().__init__(f"cancelled after {len(visited)} of {track.num_frames} frames")
        self.track, self.visited = track, visited


class Segmenter(Protocol):
    """Anything that turns frames and a seed into a MaskTrack; a tracker that is cancelled
    once it has tracked frames raises TrackingCancelled with them."""

    def segment(self, frames: Frames, seed: Seed, progress: ProgressCallback | None = None,
                cancel: threading.Event | None = None) -> MaskTrack: ...
