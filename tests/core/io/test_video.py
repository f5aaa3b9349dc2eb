"""Tests for core/io/video.py: metadata, exact random access in every codec OpenCV writes,
the decode-forward fallback, the cache, frame ranges, ROIs and bad files."""

import random
from pathlib import Path

import cv2
import numpy as np
import pytest

import dolphinfit.core.io.video as video
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.video import (
    Clip, VideoReader, crop_roi, frame_range, frames_at_fps, open_clip, step_for_fps,
)

WIDTH_PX, HEIGHT_PX, FPS, NUM_FRAMES = 160, 128, 25.0, 48
NUM_BITS = 6  # 2⁶ = 64 > NUM_FRAMES
BIT_WIDTH_PX = WIDTH_PX // NUM_BITS
BIT_ROWS = slice(44, 84)

# (fourcc, suffix) pairs that the bundled OpenCV writes and reads (reference/platform.md §5).
WRITABLE = [("mp4v", ".mp4"), ("mp4v", ".mov"), ("MJPG", ".avi"), ("XVID", ".avi"),
            ("FFV1", ".mkv"), ("VP80", ".webm"), ("VP90", ".webm"), ("HFYU", ".avi"),
            ("IYUV", ".avi")]


def _indexed_frame(idx: int) -> np.ndarray:
    """A BGR frame whose moving gradient changes every frame and whose bits spell ``idx``."""
    cols = np.arange(WIDTH_PX)[None, :] + 3 * idx
    rows = np.arange(HEIGHT_PX)[:, None]
    background = (96 + 40 * np.sin(cols / 9.0) * np.cos(rows / 13.0)).astype(np.uint8)
    frame = np.repeat(background[:, :, None], 3, axis=2)
    for bit in range(NUM_BITS):
        frame[BIT_ROWS, bit * BIT_WIDTH_PX + 2:(bit + 1) * BIT_WIDTH_PX - 2] = \
            255 if (idx >> bit) & 1 else 0
    return frame


def _read_index(rgb: np.ndarray) -> int:
    """The frame index spelt by the bit blocks of an RGB frame."""
    inner = slice(BIT_ROWS.start + 6, BIT_ROWS.stop - 6)
    return sum(1 << bit for bit in range(NUM_BITS)
               if rgb[inner, bit * BIT_WIDTH_PX + 6:(bit + 1) * BIT_WIDTH_PX - 6].mean() > 128)


def _write_clip(path, fourcc: str, frames) -> None:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*fourcc), FPS,
                             (WIDTH_PX, HEIGHT_PX))
    assert writer.isOpened()
    for frame in frames:
        writer.write(frame)
    writer.release()


@pytest.fixture(scope="module", params=WRITABLE, ids=lambda p: f"{p[0]}{p[1]}")
def indexed_clip(request, tmp_path_factory):
    """A 48-frame clip whose frames carry their own index, in one container/codec."""
    fourcc, suffix = request.param
    path = tmp_path_factory.mktemp("video") / f"indexed_{fourcc}{suffix}"
    _write_clip(path, fourcc, (_indexed_frame(i) for i in range(NUM_FRAMES)))
    return path


@pytest.fixture(scope="module")
def mp4_clip(tmp_path_factory):
    """The indexed clip as mp4v in .mp4."""
    path = tmp_path_factory.mktemp("mp4") / "indexed.mp4"
    _write_clip(path, "mp4v", (_indexed_frame(i) for i in range(NUM_FRAMES)))
    return path


class _CountingCapture:
    """Wraps a capture: counts decoded frames and can make seeks land ``seek_error`` early."""

    def __init__(self, capture, seek_error: int = 0) -> None:
        self.capture, self.seek_error, self.decoded = capture, seek_error, 0

    def set(self, prop, value):
        if prop == cv2.CAP_PROP_POS_FRAMES:
            value = max(0, value - self.seek_error)
        return self.capture.set(prop, value)

    def read(self):
        self.decoded += 1
        return self.capture.read()

    def grab(self):
        self.decoded += 1
        return self.capture.grab()

    def __getattr__(self, name):
        return getattr(self.capture, name)


def _wrap_captures(monkeypatch, seek_error: int = 0) -> list[_CountingCapture]:
    """Make every capture that video.py opens a _CountingCapture; returns the list of them."""
    opened, real_open = [], video._open_capture

    def open_wrapped(path):
        opened.append(_CountingCapture(real_open(path), seek_error))
        return opened[-1]

    monkeypatch.setattr(video, "_open_capture", open_wrapped)
    return opened


def test_metadata_of_a_written_clip(indexed_clip):
    """open_clip reports the written frame rate, frame count, size and duration."""
    clip = open_clip(indexed_clip)
    assert clip == Clip(indexed_clip, FPS, NUM_FRAMES, WIDTH_PX, HEIGHT_PX)
    assert clip.duration_s == pytest.approx(NUM_FRAMES / FPS)


def test_random_seeks_are_exact(indexed_clip):
    """60 random accesses each return the frame whose pixels spell the requested index."""
    order = random.Random(4).choices(range(NUM_FRAMES), k=60)
    with VideoReader(indexed_clip, cache_bytes=0) as reader:
        assert [_read_index(reader[i]) for i in order] == order
        assert reader.seek_is_exact


def test_sequential_frames_are_exact_and_rgb(mp4_clip):
    """Reading in order gives frames 0…T−1; frames are read-only RGB uint8 arrays."""
    with VideoReader(mp4_clip) as reader:
        frames = list(reader.frames(range(len(reader))))
    assert [_read_index(f) for _, f in frames] == list(range(NUM_FRAMES))
    first = frames[0][1]
    assert first.shape == (HEIGHT_PX, WIDTH_PX, 3) and first.dtype == np.uint8
    assert not first.flags.writeable


def test_rgb_channel_order(tmp_path):
    """A 3-frame lossless clip of a pure red BGR frame has 3 frames and reads back red in
    channel 0."""
    path = tmp_path / "red.mkv"
    red_bgr = np.zeros((HEIGHT_PX, WIDTH_PX, 3), np.uint8)
    red_bgr[..., 2] = 255
    _write_clip(path, "FFV1", [red_bgr] * 3)
    with VideoReader(path) as reader:
        assert len(reader) == 3
        np.testing.assert_allclose(reader[1].reshape(-1, 3).mean(axis=0), [255, 0, 0], atol=2)


def test_inexact_seek_falls_back_to_decoding_forward(mp4_clip, monkeypatch):
    """Seeks that land 3 frames early are detected by timestamp; frames stay exact."""
    _wrap_captures(monkeypatch, seek_error=3)
    order = random.Random(5).choices(range(NUM_FRAMES), k=30)
    with VideoReader(mp4_clip, cache_bytes=0) as reader:
        assert [_read_index(reader[i]) for i in order] == order
        assert not reader.seek_is_exact


def test_cache_serves_repeats_and_is_bounded(mp4_clip, monkeypatch):
    """A cached frame is not decoded again; a 3-frame cache forgets the oldest frames."""
    opened = _wrap_captures(monkeypatch)
    frame_bytes = WIDTH_PX * HEIGHT_PX * 3
    with VideoReader(mp4_clip, cache_bytes=3 * frame_bytes) as reader:
        capture = opened[-1]
        reader[20]
        decoded = capture.decoded
        assert _read_index(reader[20]) == 20 and capture.decoded == decoded
        for idx in range(21, 25):
            reader[idx]
        decoded = capture.decoded
        assert _read_index(reader[20]) == 20 and capture.decoded > decoded


def test_short_forward_jumps_decode_without_seeking(mp4_clip, monkeypatch):
    """Every 4th frame in order decodes forward: the seek-distrusting capture never misleads."""
    _wrap_captures(monkeypatch, seek_error=3)
    with VideoReader(mp4_clip, cache_bytes=0) as reader:
        got = [(i, _read_index(f)) for i, f in reader.frames(range(0, NUM_FRAMES, 4))]
        assert all(i == code for i, code in got)
        assert reader.seek_is_exact


def test_frame_index_outside_the_clip_raises(mp4_clip):
    """Frame −1 and frame T are IndexErrors naming the clip's range."""
    with VideoReader(mp4_clip) as reader:
        for idx in (-1, NUM_FRAMES):
            with pytest.raises(IndexError, match="outside the clip"):
                reader[idx]


def test_frame_range_and_subsampling():
    """Times map to frame indices [start, end) at 25 fps; steps and target rates subsample."""
    clip = Clip(Path("x.mp4"), 25.0, 100, 64, 48)
    np.testing.assert_array_equal(frame_range(clip, 1.0, 1.2), [25, 26, 27, 28, 29])
    np.testing.assert_array_equal(frame_range(clip, 3.9, None, step=2), [98])
    assert frame_range(clip).tolist() == list(range(100))
    assert frame_range(clip, 5.0, 6.0).size == 0
    assert (step_for_fps(clip, 5.0), step_for_fps(clip, 50.0)) == (5, 1)
    with pytest.raises(InputError):
        frame_range(clip, step=0)


def test_a_cap_on_frames_lowers_the_rate_keeping_the_spacing_even():
    """A 10-s 25-fps clip at 5 per second gives 50 frames; capped at 35 it steps by 8 (32
    frames), not 5 with some left out; a window within the cap keeps the rate."""
    clip = Clip(Path("x.mp4"), 25.0, 250, 64, 48)
    assert frames_at_fps(clip, 5.0).tolist() == list(range(0, 250, 5))
    capped = frames_at_fps(clip, 5.0, max_frames=35)
    assert capped.tolist() == list(range(0, 250, 8))
    assert len(capped) == 32
    assert frames_at_fps(clip, 5.0, 2.0, 5.0, max_frames=35).tolist() == list(range(50, 125, 5))
    assert frames_at_fps(clip, 5.0, 2.0, 5.0, max_frames=10).tolist() == list(range(50, 125, 8))
    assert frames_at_fps(clip, 5.0, max_frames=1).tolist() == [0]


def test_roi_is_native_and_padded(mp4_clip):
    """An ROI equals the frame's pixels inside it and is zero where it leaves the frame."""
    frame = np.arange(5 * 7 * 3, dtype=np.uint8).reshape(5, 7, 3)
    np.testing.assert_array_equal(crop_roi(frame, 2, 1, 3, 2), frame[1:3, 2:5])
    padded = crop_roi(frame, -1, 3, 3, 4)
    np.testing.assert_array_equal(padded[:2, 1:], frame[3:5, 0:2])
    assert not padded[2:].any() and not padded[:, 0].any()
    with VideoReader(mp4_clip) as reader:
        np.testing.assert_array_equal(reader.roi(7, 100, 90, 80, 60),
                                      crop_roi(reader[7], 100, 90, 80, 60))


def _missing(tmp_path):
    return tmp_path / "missing.mp4"


def _empty(tmp_path):
    (tmp_path / "empty.mp4").touch()
    return tmp_path / "empty.mp4"


def _text(tmp_path):
    (tmp_path / "notes.mp4").write_text("dolphin sighting notes\n" * 50)
    return tmp_path / "notes.mp4"


def _truncated(fourcc, suffix):
    def make(tmp_path):
        path = tmp_path / f"cut{suffix}"
        _write_clip(path, fourcc, (_indexed_frame(i) for i in range(NUM_FRAMES)))
        path.write_bytes(path.read_bytes()[:path.stat().st_size // 2])
        return path
    return make


@pytest.mark.parametrize("make, problem", [
    (_missing, "no such file"),
    (_empty, "empty"),
    (lambda tmp_path: tmp_path, "not a file"),
    (_text, "not a video"),
    (_truncated("mp4v", ".mp4"), "not a video"),
    (_truncated("MJPG", ".avi"), "truncated"),
], ids=["missing", "empty", "folder", "text-as-mp4", "truncated-mp4", "truncated-avi"])
def test_bad_files_raise_input_error_naming_them(tmp_path, make, problem):
    """Missing, empty, non-video and truncated files raise InputError naming file and problem."""
    path = make(tmp_path)
    with pytest.raises(InputError, match=problem) as info:
        open_clip(path)
    assert str(path) in str(info.value)
