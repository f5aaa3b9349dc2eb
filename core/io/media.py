"""Media of a project clip (DESIGN.md §8): a video, a still image or a folder of numbered
frames, all read through one :class:`~core.io.frame_source.FrameSource`.

- **video** (``kind`` "video"): core.io.video.VideoReader, exact frame access.
- **image** (``kind`` "image"): one frame. Stills have no time: their clip's fps is 1.0, a
  placeholder that makes frame k's "time" k seconds.
- **frames** (``kind`` "frames"): the folder's image files in natural order of their names
  (``f_2.png`` before ``f_10.png``), decoded on demand through a bounded cache. Every frame
  must have the first frame's size (checked as each is decoded). fps 1.0 unless given.

Image files are read by core.io.image_file (DNG through its embedded preview).
"""

import re
import threading
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.frame_source import DEFAULT_CACHE_BYTES, FrameCache, FrameSource
from dolphinfit.core.io.image_file import IMAGE_SUFFIXES, read_image
from dolphinfit.core.io.video import Clip, VideoReader

VIDEO_SUFFIXES = (".mp4", ".mov", ".avi", ".mkv", ".m4v", ".mts")
MEDIA_SUFFIXES = VIDEO_SUFFIXES + IMAGE_SUFFIXES  # for file dialogs; other files open as video
STILL_FPS = 1.0  # frames per "second" of stills and frame folders: they carry no time
_DIGITS = re.compile(r"(\d+)")


class ImageFrames(FrameSource):
    """Image files as the frames of a clip: one still ("image") or a folder's ("frames").

    ``where``: the clip's path (the file, or the folder). Safe to share between threads.
    """

    def __init__(self, paths: Sequence[Path], kind: str, where: Path, fps: float = STILL_FPS,
                 cache_bytes: int = DEFAULT_CACHE_BYTES) -> None:
        first = read_image(paths[0])
        height_px, width_px = first.shape[:2]
        self.clip = Clip(where, fps, len(paths), width_px, height_px)
        self.kind = kind
        self._paths = list(paths)
        self._lock = threading.Lock()
        self._cache = FrameCache(cache_bytes, first.nbytes)
        self._cache.get_or_load(0, lambda _: first)

    def frame(self, frame_idx: int) -> np.ndarray:
        """Frame ``frame_idx`` (0-based) as (H, W, 3) uint8 RGB, read-only."""
        frame_idx = self._checked_index(frame_idx)
        with self._lock:
            return self._cache.get_or_load(frame_idx, self._read)

    def close(self) -> None:
        """Drop the cache."""
        with self._lock:
            self._cache.clear()

    def _read(self, frame_idx: int) -> np.ndarray:
        """Decode one file; InputError naming it and the folder when its size differs."""
        path = self._paths[frame_idx]
        rgb = read_image(path)
        if rgb.shape[:2] != (self.clip.height_px, self.clip.width_px):
            raise InputError(f"{self.clip.path}: frame {path.name} is {rgb.shape[1]}×"
                             f"{rgb.shape[0]} px but {self._paths[0].name} is "
                             f"{self.clip.width_px}×{self.clip.height_px} px")
        return rgb


def natural_key(name: str) -> list[int | str]:
    """Sort key comparing the runs of digits in ``name`` as numbers (f_2 before f_10)."""
    return [int(part) if part.isdigit() else part.lower() for part in _DIGITS.split(name)]


def frame_files(folder: Path) -> list[Path]:
    """The image files of ``folder`` in natural order; InputError naming it if there are none."""
    files = [p for p in folder.iterdir() if p.is_file() and not p.name.startswith(".")
             and p.suffix.lower() in IMAGE_SUFFIXES]
    if not files:
        raise InputError(f"{folder}: no image files ({', '.join(IMAGE_SUFFIXES)}) in the folder")
    return sorted(files, key=lambda p: natural_key(p.name))


def open_media(path: Path | str, fps: float | None = None) -> FrameSource:
    """The media at ``path``: a folder of frames, a still image (by suffix) or else a video.

    ``fps``: a frame folder's frame rate (default STILL_FPS); videos carry their own and stills
    have none. InputError naming the path when it is missing or cannot be read.
    """
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such file or folder")
    if path.is_dir():
        if fps is not None and not fps > 0:
            raise InputError(f"{path}: frame rate must be positive, got {fps}")
        return ImageFrames(frame_files(path), "frames", path, STILL_FPS if fps is None else fps)
    if path.suffix.lower() in IMAGE_SUFFIXES:
        return ImageFrames([path], "image", path)
    return VideoReader(path)


def video_files(path: Path) -> list[Path]:
    """The video at ``path``, or the videos of a folder in natural order of their names;
    InputError when there is none."""
    path = Path(path)
    if path.is_dir():
        videos = sorted((p for p in path.iterdir() if p.suffix.lower() in VIDEO_SUFFIXES),
                        key=lambda p: natural_key(p.name))
        if not videos:
            raise InputError(f"{path}: no video in the folder ({', '.join(VIDEO_SUFFIXES)})")
        return videos
    if not path.exists():
        raise InputError(f"{path}: no such file or folder")
    return [path]
