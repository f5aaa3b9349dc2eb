"""Video clips: metadata, exact random access by frame index, a bounded frame cache, frame
ranges and regions of interest at native resolution.

Clips are decoded by OpenCV's FFmpeg back-end, so any container and codec it reads will do
(DJI writes H.264/H.265 in .MP4/.MOV). Frames come out as (H, W, 3) uint8 RGB arrays, read-only
(they may be shared with the cache).

Exact access (DESIGN.md §8): OpenCV seeks by moving the demuxer to the keyframe before the
target and decoding forward to the target's timestamp. The reader checks every seek against
the decoded frame's timestamp (frame k is shown at k / fps). Seeking is not exact on every
long-GOP camera file (OpenCV issue #9053, reference/platform.md §5): at the first mismatch the
reader stops trusting seeks for that clip and reaches frames by decoding forward, counting
frames from the start or from where it stands. Short jumps forward always decode forward.

A reader holds one decoder and is safe to share between threads (one lock), but decoding is
serial: give each worker its own reader to decode in parallel.
"""

import threading
from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.frame_source import DEFAULT_CACHE_BYTES, Clip, FrameCache, FrameSource

# FFmpeg's interrupt callback aborts opening or reading after this long, so a bogus or
# unreachable file cannot hang (the timeouts are capture parameters of OpenCV's FFmpeg back-end).
OPEN_TIMEOUT_MS = 10_000
READ_TIMEOUT_MS = 10_000

# A jump forward of up to this many frames decodes forward instead of seeking: a seek decodes
# from the preceding keyframe anyway, and camera GOPs are 12–60 frames long.
MAX_DECODE_FORWARD = 16
SEEK_TOLERANCE_FRAMES = 0.5  # a sought frame's timestamp must lie within half a frame
# Containers that estimate the frame count from duration × fps can overstate it by a frame or
# two; a larger shortfall at the end of the clip means it is truncated.
FRAME_COUNT_SLACK = 2
TAIL_CHECK_FRAMES = 8  # how far before the announced end the truncation check starts decoding


def _check_file(path: Path) -> None:
    """InputError unless ``path`` is an existing, non-empty regular file."""
    if not path.exists():
        raise InputError(f"{path}: no such file")
    if not path.is_file():
        raise InputError(f"{path}: not a file")
    if path.stat().st_size == 0:
        raise InputError(f"{path}: the file is empty")


def _open_capture(path: Path) -> cv2.VideoCapture:
    """An opened FFmpeg capture with open/read timeouts; InputError if FFmpeg cannot read it."""
    capture = cv2.VideoCapture(
        str(path), cv2.CAP_FFMPEG,
        [cv2.CAP_PROP_OPEN_TIMEOUT_MSEC, OPEN_TIMEOUT_MS,
         cv2.CAP_PROP_READ_TIMEOUT_MSEC, READ_TIMEOUT_MS],
    )
    if not capture.isOpened():
        raise InputError(f"{path}: not a video that OpenCV/FFmpeg can decode "
                         "(damaged, truncated, or not a video file)")
    return capture


def _decodable_end(capture: cv2.VideoCapture, num_frames: int) -> int:
    """Index one past the last frame that decodes, looking only near the announced end.

    The capture has just read frame 0; a short clip is read on from there, a longer one from
    TAIL_CHECK_FRAMES before its announced end.
    """
    end = max(1, num_frames - TAIL_CHECK_FRAMES)
    if end > 1 and not capture.set(cv2.CAP_PROP_POS_FRAMES, end):
        return end
    while end < num_frames and capture.grab():
        end += 1
    return end


def open_clip(path: Path | str) -> Clip:
    """Read and check a clip's metadata; InputError naming the file and the problem.

    Checks that the file exists and is not empty, that FFmpeg opens it, that it reports a frame
    rate, size and frame count, that its first frame decodes and that it is not truncated (the
    frames near the announced end decode). A count overstated by at most FRAME_COUNT_SLACK
    frames is corrected.
    """
    path = Path(path)
    _check_file(path)
    capture = _open_capture(path)
    try:
        fps = capture.get(cv2.CAP_PROP_FPS)
        num_frames = int(capture.get(cv2.CAP_PROP_FRAME_COUNT))
        width_px = int(capture.get(cv2.CAP_PROP_FRAME_WIDTH))
        height_px = int(capture.get(cv2.CAP_PROP_FRAME_HEIGHT))
        if not fps > 0 or num_frames <= 0 or width_px <= 0 or height_px <= 0:
            raise InputError(f"{path}: no usable video stream (fps {fps:g}, {num_frames} frames, "
                             f"{width_px}x{height_px} px)")
        if not capture.grab():
            raise InputError(f"{path}: the first frame cannot be decoded")
        end = _decodable_end(capture, num_frames)
    finally:
        capture.release()
    if end < num_frames - FRAME_COUNT_SLACK:
        raise InputError(f"{path}: truncated or damaged: the file announces {num_frames} frames "
                         f"but frame {end} cannot be decoded")
    return Clip(path, fps, end, width_px, height_px)


def frame_range(clip: Clip, start_s: float | None = None, end_s: float | None = None,
                step: int = 1) -> np.ndarray:
    """Indices of the frames shown in [start_s, end_s), every ``step``-th: (N,) int64.

    ``None`` means the start or the end of the clip.
    """
    if step < 1:
        raise InputError(f"frame step must be at least 1, got {step}")
    first = 0 if start_s is None else max(0, int(np.ceil(start_s * clip.fps - 1e-9)))
    stop = clip.num_frames if end_s is None else min(clip.num_frames,
                                                     int(np.ceil(end_s * clip.fps - 1e-9)))
    return np.arange(first, max(first, stop), step, dtype=np.int64)


def frames_at_fps(clip: Clip, fps: float, start_s: float | None = None,
                  end_s: float | None = None, max_frames: int | None = None) -> np.ndarray:
    """Indices of the frames in [start_s, end_s) subsampled closest to ``fps`` frames per
    second (``frame_range`` at ``step_for_fps``): the frames a fit at that rate uses. With
    ``max_frames``, a window that would give more is subsampled at the smallest larger step
    that gives at most that many (evenly spaced still, as the fit's motion priors assume)."""
    window = frame_range(clip, start_s, end_s)
    step = step_for_fps(clip, fps)
    if max_frames is not None:
        step = max(step, -(-len(window) // max_frames))
    return window[::step]


def step_for_fps(clip: Clip, fps: float) -> int:
    """The frame step that subsamples ``clip`` closest to ``fps`` frames per second (≥ 1)."""
    if not fps > 0:
        raise InputError(f"frame rate must be positive, got {fps}")
    return max(1, round(clip.fps / fps))


def crop_roi(frame: np.ndarray, x0_px: int, y0_px: int, width_px: int, height_px: int,
             fill: int = 0) -> np.ndarray:
    """A (height_px, width_px, ...) window of ``frame`` with top-left pixel (x0_px, y0_px).

    Native resolution, no resampling; parts outside the frame are ``fill``. The matching camera
    is ``camera.crop(x0_px, y0_px, width_px, height_px)`` (core/camera.py).
    """
    out = np.full((height_px, width_px, *frame.shape[2:]), fill, dtype=frame.dtype)
    src_x0, src_y0 = max(x0_px, 0), max(y0_px, 0)
    src_x1 = min(x0_px + width_px, frame.shape[1])
    src_y1 = min(y0_px + height_px, frame.shape[0])
    if src_x1 > src_x0 and src_y1 > src_y0:
        out[src_y0 - y0_px:src_y1 - y0_px, src_x0 - x0_px:src_x1 - x0_px] = \
            frame[src_y0:src_y1, src_x0:src_x1]
    return out


class VideoReader(FrameSource):
    """Exact frame access to one clip, with a bounded least-recently-used frame cache.

    ``reader[k]`` or ``reader.frame(k)`` gives frame k as (H, W, 3) uint8 RGB, read-only.
    ``len(reader)`` is the clip's frame count. Use as a context manager, or call ``close``.
    """

    kind = "video"

    def __init__(self, clip: Clip | Path | str, cache_bytes: int = DEFAULT_CACHE_BYTES) -> None:
        self.clip = clip if isinstance(clip, Clip) else open_clip(clip)
        self._cache = FrameCache(cache_bytes, self.clip.width_px * self.clip.height_px * 3)
        self._lock = threading.Lock()
        self._seek_is_exact = True
        self._capture = _open_capture(self.clip.path)
        self._next_idx = 0  # the frame that the capture's next read returns

    def close(self) -> None:
        """Release the decoder and drop the cache."""
        with self._lock:
            self._capture.release()
            self._cache.clear()

    @property
    def seek_is_exact(self) -> bool:
        """False once a seek landed on the wrong frame; the reader then decodes forward."""
        return self._seek_is_exact

    def frame(self, frame_idx: int) -> np.ndarray:
        """Frame ``frame_idx`` (0-based) as (H, W, 3) uint8 RGB, read-only.

        Ascending indices (``frames``) decode without seeking.
        """
        frame_idx = self._checked_index(frame_idx)
        with self._lock:
            return self._cache.get_or_load(
                frame_idx, lambda idx: cv2.cvtColor(self._decode(idx), cv2.COLOR_BGR2RGB))

    def roi(self, frame_idx: int, x0_px: int, y0_px: int, width_px: int,
            height_px: int) -> np.ndarray:
        """A native-resolution window of frame ``frame_idx`` (see ``crop_roi``)."""
        return crop_roi(self.frame(frame_idx), x0_px, y0_px, width_px, height_px)

    def _decode(self, frame_idx: int) -> np.ndarray:
        """Frame ``frame_idx`` as BGR, from the decoder (the lock is held)."""
        jump = frame_idx - self._next_idx
        if jump != 0 and not 0 < jump <= MAX_DECODE_FORWARD:
            if self._seek_is_exact:
                bgr = self._read_sought(frame_idx)
                if bgr is not None:
                    return bgr
            if frame_idx < self._next_idx:
                self._rewind()
        while self._next_idx < frame_idx:
            if not self._capture.grab():
                raise self._undecodable(self._next_idx)
            self._next_idx += 1
        ok, bgr = self._capture.read()
        if not ok:
            raise self._undecodable(frame_idx)
        self._next_idx = frame_idx + 1
        return bgr

    def _read_sought(self, frame_idx: int) -> np.ndarray | None:
        """Seek to and read ``frame_idx``; None (and seeks distrusted) if it landed elsewhere."""
        self._capture.set(cv2.CAP_PROP_POS_FRAMES, frame_idx)
        ok, bgr = self._capture.read()
        shown_s = self._capture.get(cv2.CAP_PROP_POS_MSEC) / 1000.0
        expected_s = frame_idx / self.clip.fps
        if ok and abs(shown_s - expected_s) <= SEEK_TOLERANCE_FRAMES / self.clip.fps:
            self._next_idx = frame_idx + 1
            return bgr
        self._seek_is_exact = False
        self._rewind()
        return None

    def _rewind(self) -> None:
        """Reopen the decoder at frame 0 (exact without seeking)."""
        self._capture.release()
        self._capture = _open_capture(self.clip.path)
        self._next_idx = 0

    def _undecodable(self, frame_idx: int) -> InputError:
        return InputError(f"{self.clip.path}: frame {frame_idx} of {self.clip.num_frames} "
                          "cannot be decoded (truncated or damaged file?)")
