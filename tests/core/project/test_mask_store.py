"""Tests for core/project/mask_store.py: where masks are kept, lossless round trip, checks,
coverage, one-frame edits, outlines and brush segments."""

from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import MaskTrack
from dolphinfit.core.io.video import Clip
from dolphinfit.core.project.mask_store import (
    coverage,
    load_track,
    masks_file,
    outlines,
    paint_segment,
    save_track,
    with_frame,
)

T, H, W = 5, 30, 40


def _masks() -> np.ndarray:
    """(T, H, W) bool: an ellipse moving left until it touches the left border; frame 3 empty."""
    masks = np.zeros((T, H, W), np.uint8)
    for t in range(T):
        if t != 3:
            cv2.ellipse(masks[t], (20 - 5 * t, 15), (8, 4), 0, 0, 360, 1, -1)
    return masks.astype(bool)


def _clip(num_frames: int = T, width_px: int = W, height_px: int = H) -> Clip:
    return Clip(Path("clip.mp4"), 25.0, num_frames, width_px, height_px)


def test_masks_file_is_beside_the_project():
    path = masks_file(Path("/data/survey.dolphinfit"), "media/DJI_0042.MP4")
    assert path.parent == Path("/data/survey.masks") and path.name.startswith("DJI_0042-")
    other_day = masks_file(Path("/data/survey.dolphinfit"), "day2/DJI_0042.MP4")
    assert other_day != path  # the same camera file name from another card


def test_round_trip_is_exact(tmp_path):
    masks = _masks()
    path = masks_file(tmp_path / "p.dolphinfit", "clip.mp4")
    save_track(MaskTrack.from_array(masks, "test"), path)
    track = load_track(path, _clip())
    np.testing.assert_array_equal(track.stack(), masks)
    np.testing.assert_array_equal(track.is_visible, [True, True, True, False, True])
    assert [p.name for p in path.parent.iterdir()] == [path.name]  # no temporary left


@pytest.mark.parametrize("clip, what", [(_clip(num_frames=T + 1), "frames"),
                                        (_clip(width_px=W + 2), "expected 42x30 px")])
def test_masks_that_do_not_fit_the_clip_are_refused(tmp_path, clip, what):
    path = tmp_path / "m.npz"
    save_track(MaskTrack.from_array(_masks(), "test"), path)
    with pytest.raises(InputError, match=what) as error:
        load_track(path, clip)
    assert str(path) in str(error.value)


def test_a_missing_file_is_named(tmp_path):
    with pytest.raises(InputError, match="missing.npz"):
        load_track(tmp_path / "missing.npz", _clip())


def test_coverage_flags_the_left_border():
    masks = _masks()  # x centre 20, 15, 10, –, 0 with semi-axis 8: frame 4 reaches column 0
    result = coverage(MaskTrack.from_array(masks, "test"))
    np.testing.assert_array_equal(result.visible, [True, True, True, False, True])
    np.testing.assert_array_equal(result.touches_border, [False, False, False, False, True])
    np.testing.assert_array_equal(result.area_px, masks.sum(axis=(1, 2)))
    assert result.area_px.dtype == np.int64 and result.num_frames == T


def test_with_frame_replaces_one_frame_only():
    masks = _masks()
    track = MaskTrack.from_array(masks, "test")
    new = np.zeros((H, W), bool)
    new[5:9, 5:9] = True
    edited = with_frame(with_frame(track, 3, new), 0, np.zeros((H, W), bool))
    np.testing.assert_array_equal(edited.mask(3), new)
    assert not edited.is_visible[0] and edited.is_visible[3]
    for t in (1, 2, 4):
        np.testing.assert_array_equal(edited.mask(t), masks[t])
    np.testing.assert_array_equal(track.stack(), masks)  # the original is unchanged
    new[:] = False
    assert edited.mask(3).any()  # a copy was kept
    with pytest.raises(ValueError, match="40x30"):
        with_frame(track, 0, np.zeros((H + 1, W), bool))
    with pytest.raises(IndexError):
        with_frame(track, T, new)


def test_outlines_run_through_edge_pixel_centres():
    mask = np.zeros((H, W), bool)
    mask[10:15, 20:31] = True
    mask[2, 2] = True
    found = sorted(outlines(mask), key=len)
    assert len(found) == 2
    np.testing.assert_array_equal(found[0], [[2.0, 2.0]])
    box = found[1]
    np.testing.assert_array_equal(box.min(axis=0), [20, 10])
    np.testing.assert_array_equal(box.max(axis=0), [30, 14])
    assert outlines(np.zeros((H, W), bool)) == []


def test_paint_segment_paints_a_capsule_and_erases_it():
    mask = np.zeros((H, W), bool)
    paint_segment(mask, (10.0, 15.0), (30.0, 15.0), 3.0, True)
    assert mask[:, 20].sum() == 7  # rows 12…18: centres within 3 px
    assert mask[15, 7] and not mask[15, 6] and mask[15, 33] and not mask[15, 34]
    assert not mask[12, 8]  # the rounded end: (2, 3) px from (10, 15) is beyond 3 px
    paint_segment(mask, (10.0, 15.0), (30.0, 15.0), 3.0, False)
    assert not mask.any()
    paint_segment(mask, (-10.0, -10.0), (-10.0, -10.0), 2.0, True)  # outside: nothing
    assert not mask.any()
