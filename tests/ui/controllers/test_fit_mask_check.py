"""What the fit panel says of the masks of a fit's frames (counting Coverage, no images)."""

import numpy as np

from dolphinfit.core.project.mask_store import Coverage
from dolphinfit.ui.controllers.fit_controller import mask_check

FRAMES = np.arange(0, 20, 2)  # 10 frames to fit


def _coverage(visible: list[int], border: list[int] = ()) -> Coverage:
    """20 frames: masks on ``visible``, those of ``border`` touching the image border."""
    is_visible, touches = np.zeros(20, bool), np.zeros(20, bool)
    is_visible[visible], touches[list(border)] = True, True
    return Coverage(is_visible, touches, is_visible * 100)


def test_a_range_without_usable_masks_cannot_start():
    note, can_start = mask_check(FRAMES, _coverage([1, 3, 19]), True)  # masks off the frames
    assert not can_start and note.startswith("⚠ no usable masks in frames 0–18: track the "
                                             "animal again") and "pick another range" in note
    note, can_start = mask_check(FRAMES, _coverage([0, 2], border=[0, 2]), True)
    assert not can_start and "frames 0–18 (2 touch the image border)" in note
    note, can_start = mask_check(FRAMES, None, False)
    assert not can_start and "this clip has no masks" in note and "Clip → Masks…" in note


def test_a_partly_masked_range_says_how_many_and_a_masked_one_nothing():
    note, can_start = mask_check(FRAMES, _coverage([0, 2, 4, 6], border=[6]), True)
    assert can_start and note.startswith("3 of the 10 frames to fit (frames 0–18) have a "
                                         "usable mask")
    assert mask_check(FRAMES, _coverage(list(FRAMES)), True) == ("", True)
    assert mask_check(FRAMES, None, True) == ("", True)  # still being read: nothing known
