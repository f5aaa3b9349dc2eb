"""Tests for core/io/media.py and core/io/image_file.py: stills, DNG previews, folders of
numbered frames and videos behind one FrameSource; errors naming the path."""

import re

import cv2
import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.frame_source import FrameSource
from dolphinfit.core.io.media import MEDIA_SUFFIXES, open_media

WIDTH_PX, HEIGHT_PX = 64, 48


def _smooth_rgb(width_px: int = WIDTH_PX, height_px: int = HEIGHT_PX) -> np.ndarray:
    """A smooth colour gradient (survives JPEG compression within a few grey levels)."""
    v, u = np.mgrid[:height_px, :width_px]
    return np.stack([4 * u % 256, 5 * v % 256, np.full_like(u, 90)], axis=-1).astype(np.uint8)


def _write(path, rgb: np.ndarray) -> None:
    assert cv2.imwrite(str(path), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR))


def test_png_still_is_one_exact_read_only_frame(tmp_path):
    """A PNG opens as kind "image": one frame at fps 1.0, its pixels exactly, read-only."""
    rgb = _smooth_rgb()
    _write(tmp_path / "still.png", rgb)
    with open_media(tmp_path / "still.png") as media:
        assert isinstance(media, FrameSource) and media.kind == "image"
        clip = media.clip
        assert (clip.fps, clip.num_frames, clip.width_px, clip.height_px) == \
            (1.0, 1, WIDTH_PX, HEIGHT_PX)
        frame = media.frame(0)
        np.testing.assert_array_equal(frame, rgb)
        assert frame.dtype == np.uint8 and not frame.flags.writeable
        with pytest.raises(IndexError, match="frame 1 is outside"):
            media.frame(1)


def test_jpeg_still_decodes_to_rgb(tmp_path):
    """A JPEG comes out RGB (not BGR), within JPEG's error."""
    rgb = _smooth_rgb()
    _write(tmp_path / "still.JPG", rgb)
    with open_media(tmp_path / "still.JPG") as media:
        assert np.abs(media.frame(0).astype(int) - rgb).mean() < 3


def test_dng_reads_the_largest_embedded_jpeg(tmp_path):
    """Junk, a small thumbnail, junk, the full preview, junk: the preview is read."""
    preview = _smooth_rgb()
    thumb = np.full((8, 16, 3), 200, np.uint8)
    encoded = [cv2.imencode(".jpg", cv2.cvtColor(image, cv2.COLOR_RGB2BGR))[1].tobytes()
               for image in (thumb, preview)]
    junk = bytes(range(256)) * 3
    (tmp_path / "raw.dng").write_bytes(b"II*\x00" + junk + encoded[0] + junk + encoded[1] + junk)
    with open_media(tmp_path / "raw.dng") as media:
        assert media.kind == "image"
        assert (media.clip.width_px, media.clip.height_px) == (WIDTH_PX, HEIGHT_PX)
        assert np.abs(media.frame(0).astype(int) - preview).mean() < 3
    (tmp_path / "empty.dng").write_bytes(b"II*\x00" + junk)
    with pytest.raises(InputError, match="empty.dng: no embedded JPEG preview"):
        open_media(tmp_path / "empty.dng")


def test_folder_of_frames_in_natural_order(tmp_path):
    """f_1, f_2, f_10 in that order (not f_1, f_10, f_2); fps 1.0 unless given; a frame of
    another size raises naming the folder when it is decoded."""
    for number in (2, 10, 1):
        _write(tmp_path / f"f_{number}.png", np.full((HEIGHT_PX, WIDTH_PX, 3), number, np.uint8))
    (tmp_path / "notes.txt").write_text("not a frame")
    with open_media(tmp_path) as media:
        assert media.kind == "frames" and media.clip.fps == 1.0 and len(media) == 3
        assert [int(frame[0, 0, 0]) for _, frame in media.frames(range(3))] == [1, 2, 10]
    _write(tmp_path / "f_11.png", np.zeros((HEIGHT_PX, WIDTH_PX + 1, 3), np.uint8))
    with open_media(tmp_path, fps=5.0) as media:
        assert media.clip.fps == 5.0 and media.clip.num_frames == 4
        message = f"{tmp_path}: frame f_11.png is 65×48 px but f_1.png is 64×48 px"
        with pytest.raises(InputError, match=re.escape(message)):
            media.frame(3)


def test_video_opens_through_the_video_reader(tmp_path):
    """An mp4v clip: kind "video", its fps, count and size; frame k has its colour."""
    path = tmp_path / "clip.mp4"
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), 10.0,
                             (WIDTH_PX, HEIGHT_PX))
    for k in range(5):
        writer.write(np.full((HEIGHT_PX, WIDTH_PX, 3), (0, 40 * k, 200), np.uint8))  # BGR
    writer.release()
    assert ".mp4" in MEDIA_SUFFIXES and ".dng" in MEDIA_SUFFIXES
    with open_media(path) as media:
        clip = media.clip
        assert media.kind == "video"
        assert (clip.fps, clip.num_frames, clip.width_px, clip.height_px) == \
            (10.0, 5, WIDTH_PX, HEIGHT_PX)
        np.testing.assert_allclose(media[3].reshape(-1, 3).mean(axis=0), (200, 120, 0), atol=4)


def test_unreadable_media_raise_naming_the_path(tmp_path):
    """A missing path, an empty folder and a text file named .png raise InputError."""
    with pytest.raises(InputError, match="none.mp4: no such file or folder"):
        open_media(tmp_path / "none.mp4")
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="empty: no image files"):
        open_media(tmp_path / "empty")
    (tmp_path / "fake.png").write_text("hello")
    with pytest.raises(InputError, match="fake.png: not an image that OpenCV can decode"):
        open_media(tmp_path / "fake.png")
