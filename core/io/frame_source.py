"""The interface shared by every kind of media (video, still image, folder of frames) and the
bounded least-recently-used frame cache its implementations keep.

A :class:`FrameSource` has a ``clip`` (:class:`Clip`: path, fps, frame count, size) and a
``kind``, and gives frame k as an (H, W, 3) uint8 RGB array, read-only (it may be shared with
the cache). Use it as a context manager, or call ``close``.
"""

from abc import ABC, abstractmethod
from collections import OrderedDict
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType
from typing import Self

import numpy as np

DEFAULT_CACHE_BYTES = 512 * 2**20  # ~20 decoded 4K frames or ~90 at 1080p: smooth scrubbing


@dataclass(frozen=True)
class Clip:
    """A video clip's metadata: frame rate (frames per second), frame count and size in pixels."""

    path: Path
    fps: float
    num_frames: int
    width_px: int
    height_px: int

    @property
    def duration_s(self) -> float:
        """Length of the clip, seconds (num_frames / fps)."""
        return self.num_frames / self.fps

    def frame_time_s(self, frame_idx: np.ndarray | int) -> np.ndarray:
        """Presentation time of frame(s) ``frame_idx``, seconds from the first frame."""
        return np.asarray(frame_idx, dtype=np.float64) / self.fps


class FrameCache:
    """Decoded frames by index, at most ``cache_bytes`` of them (at least one frame).

    Not locked: the owner serialises calls.
    """

    def __init__(self, cache_bytes: int, frame_bytes: int) -> None:
        self._max_frames = max(1, cache_bytes // frame_bytes)
        self._frames: OrderedDict[int, np.ndarray] = OrderedDict()

    def get_or_load(self, frame_idx: int, load: Callable[[int], np.ndarray]) -> np.ndarray:
        """The cached frame, else ``load(frame_idx)`` made read-only and cached."""
        frame = self._frames.get(frame_idx)
        if frame is not None:
            self._frames.move_to_end(frame_idx)
            return frame
        frame = load(frame_idx)
        frame.flags.writeable = False
        self._frames[frame_idx] = frame
        if len(self._frames) > self._max_frames:
            self._frames.popitem(last=False)
        return frame

    def clear(self) -> None:
        """Forget every frame."""
        self._frames.clear()


class FrameSource(ABC):
    """Frames of one media item by index: ``source[k]`` or ``source.frame(k)``.

    ``kind``: "video", "image" or "frames"; ``len(source)`` is the clip's frame count.
    """

    clip: Clip
    kind: str

    @abstractmethod
    def frame(self, frame_idx: int) -> np.ndarray:
        """Frame ``frame_idx`` (0-based) as (H, W, 3) uint8 RGB, read-only."""

    @abstractmethod
    def close(self) -> None:
        """Release files and decoders and drop the cache."""

    def __len__(self) -> int:
        return self.clip.num_frames

    def __getitem__(self, frame_idx: int) -> np.ndarray:
        return self.frame(frame_idx)

    def __enter__(self) -> Self:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 traceback: TracebackType | None) -> None:
        self.close()

    def frames(self, frame_idx: Iterable[int]) -> Iterator[tuple[int, np.ndarray]]:
        """(index, frame) for each index in order."""
        for idx in frame_idx:
            yield int(idx), self.frame(idx)

    def _checked_index(self, frame_idx: int) -> int:
        """``frame_idx`` as an int; IndexError naming the media unless it is a frame of it."""
        frame_idx = int(frame_idx)
        if not 0 <= frame_idx < self.clip.num_frames:
            raise IndexError(f"{self.clip.path}: frame {frame_idx} is outside the clip "
                             f"(0…{self.clip.num_frames - 1})")
        return frame_idx
