"""Tests for core/io/masks.py: PNG folders, mask videos and .npz files, checks and export."""

from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import (
    MaskTrack,
    check_against_clip,
    read_masks,
    write_masks,
)
from dolphinfit.core.io.video import Clip

T, H, W = 6, 48, 64


def _ellipse_masks() -> np.ndarray:
    """(T, H, W) bool: an ellipse moving right, absent in frames 2 and 5."""
    masks = np.zeros((T, H, W), np.uint8)
    for t in range(T):
        if t not in (2, 5):
            cv2.ellipse(masks[t], (16 + 4 * t, 24), (12, 5), 10, 0, 360, 1, -1)
    return masks.astype(bool)


def _clip(num_frames: int = T, width_px: int = W, height_px: int = H) -> Clip:
    return Clip(Path("clip.mp4"), 25.0, num_frames, width_px, height_px)


def test_png_folder_round_trip(tmp_path):
    """Masks written as %06d.png read back equal, with empty frames not visible."""
    truth = _ellipse_masks()
    write_masks(MaskTrack.from_array(truth, "test"), tmp_path / "masks")
    assert sorted(p.name for p in (tmp_path / "masks").iterdir())[:2] == ["000000.png",
                                                                          "000001.png"]
    track = read_masks(tmp_path / "masks", _clip())
    assert track.is_visible.tolist() == [True, True, False, True, True, False]
    np.testing.assert_array_equal(track.stack(), truth)
    assert track.source == f"png folder {tmp_path / 'masks'}"


def test_png_folder_missing_frames_are_not_visible(tmp_path):
    """Frames without a PNG are not visible; without a clip the track ends at the last file."""
    block = np.zeros((H, W), np.uint8)
    block[10:20, 5:40] = 255
    for idx in (1, 3):
        cv2.imwrite(str(tmp_path / f"{idx:06d}.png"), block)
    (tmp_path / "notes.txt").write_text("ignored")
    track = read_masks(tmp_path)
    assert track.is_visible.tolist() == [False, True, False, True]
    assert not track.mask(0).any() and track.mask(1).sum() == 10 * 35
    assert read_masks(tmp_path, _clip(num_frames=10)).num_frames == 10


def test_png_of_the_wrong_size_raises_naming_it(tmp_path):
    """A PNG whose size differs from the clip raises InputError naming the file and sizes."""
    cv2.imwrite(str(tmp_path / "000000.png"), np.zeros((H, W + 1), np.uint8))
    with pytest.raises(InputError, match=r"000000.png: mask is 65x48 px, expected 64x48 px"):
        read_masks(tmp_path, _clip())


def test_png_beyond_the_clip_raises(tmp_path):
    """A PNG indexed past the clip's last frame raises InputError naming it."""
    cv2.imwrite(str(tmp_path / "000009.png"), np.zeros((H, W), np.uint8))
    with pytest.raises(InputError, match="000009.png: frame 9 is beyond the clip's 6 frames"):
        read_masks(tmp_path, _clip())


def test_unreadable_png_raises(tmp_path):
    """A file named like a mask that is not a PNG raises InputError naming it."""
    (tmp_path / "000000.png").write_text("not an image")
    with pytest.raises(InputError, match="000000.png: not a readable PNG"):
        read_masks(tmp_path)


@pytest.mark.parametrize("fourcc, suffix, min_iou", [("FFV1", ".mkv", 1.0),
                                                     ("mp4v", ".mp4", 0.9)])
def test_mask_video(tmp_path, fourcc, suffix, min_iou):
    """A mask video reads back close to the truth (exact if lossless); black frames are not
    visible."""
    truth = _ellipse_masks()
    path = tmp_path / f"masks{suffix}"
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*fourcc), 25.0, (W, H))
    for mask in truth:
        writer.write(np.repeat(mask[:, :, None].astype(np.uint8) * 255, 3, axis=2))
    writer.release()
    track = read_masks(path, _clip())
    assert track.is_visible.tolist() == truth.any(axis=(1, 2)).tolist()
    for t in np.flatnonzero(track.is_visible):
        got = track.mask(t)
        assert (got & truth[t]).sum() / (got | truth[t]).sum() >= min_iou


def test_npz_round_trip_with_visible_flags(tmp_path):
    """An .npz keeps the masks; its is_visible flags switch off frames with masks."""
    truth = _ellipse_masks()
    flags = np.array([True, False, True, True, True, True])
    write_masks(MaskTrack.from_array(truth, "test", flags), tmp_path / "m.npz")
    track = read_masks(tmp_path / "m.npz", _clip())
    assert track.is_visible.tolist() == [True, False, False, True, True, False]
    np.testing.assert_array_equal(track.mask(3), truth[3])
    assert not track.mask(1).any()


def test_npz_without_masks_raises(tmp_path):
    """An .npz without a masks array raises InputError naming it."""
    np.savez(tmp_path / "x.npz", other=np.zeros(3))
    with pytest.raises(InputError, match="no 'masks' array"):
        read_masks(tmp_path / "x.npz")


def test_frame_count_must_match_the_clip():
    """Masks for 6 frames against a 7-frame clip raise InputError giving both counts."""
    track = MaskTrack.from_array(_ellipse_masks(), "test masks")
    with pytest.raises(InputError, match="test masks: 6 frames of masks for the 7 frames"):
        check_against_clip(track, _clip(num_frames=7))


def test_missing_path_raises(tmp_path):
    """A path that does not exist raises InputError naming it."""
    with pytest.raises(InputError, match="no such file or folder"):
        read_masks(tmp_path / "nothing")


@pytest.mark.parametrize("keep", [100, 180, 200], ids=["half", "3/4", "all"])
def test_truncated_npz_raises_naming_it(tmp_path, keep):
    """An .npz cut short anywhere is an InputError naming the file, not a zip traceback."""
    write_masks(MaskTrack.from_array(_ellipse_masks(), "test"), tmp_path / "m.npz")
    data = (tmp_path / "m.npz").read_bytes()
    (tmp_path / "m.npz").write_bytes(data[:len(data) * keep // 200 - (keep == 200)])
    with pytest.raises(InputError, match=f"{tmp_path / 'm.npz'}: not a readable .npz file"):
        read_masks(tmp_path / "m.npz")


def test_all_white_and_inverted_masks_are_named(tmp_path):
    """Masks covering more than 90 % of the frame are refused, naming those frames."""
    masks = _ellipse_masks()
    masks[1] = True                    # all white
    masks[4] = ~_ellipse_masks()[4]   # inverted: the water marked as dolphin
    np.savez(tmp_path / "m.npz", masks=masks)
    with pytest.raises(InputError, match=r"m.npz: 2 mask\(s\) cover more than 90% of the "
                                         r"frame .*: frame 1, frame 4"):
        read_masks(tmp_path / "m.npz")


def test_all_empty_masks_are_refused(tmp_path):
    """Masks with no dolphin pixel in any frame are an error listing the frames."""
    np.savez(tmp_path / "m.npz", masks=np.zeros((T, H, W), np.uint8))
    with pytest.raises(InputError, match=r"m.npz: all 6 masks are empty \(frames 0–5\)"):
        read_masks(tmp_path / "m.npz")


def test_mask_folder_with_other_files_is_refused_and_kept(tmp_path):
    """Writing masks replaces the whole folder, so one holding other files is refused."""
    (tmp_path / "clip.mp4").write_text("video")
    with pytest.raises(InputError, match=r"holds other things than mask PNGs \(clip.mp4\)"):
        write_masks(MaskTrack.from_array(_ellipse_masks(), "test"), tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["clip.mp4"]


def test_rewriting_a_mask_folder_drops_old_frames(tmp_path):
    """A shorter track written over a longer one leaves exactly its own PNGs."""
    write_masks(MaskTrack.from_array(_ellipse_masks(), "test"), tmp_path / "m")
    write_masks(MaskTrack.from_array(_ellipse_masks()[:3], "test"), tmp_path / "m")
    assert sorted(p.name for p in (tmp_path / "m").iterdir()) == [f"{t:06d}.png"
                                                                   for t in range(3)]
