"""The automatic seed's pieces: which frames it looks at, lengths, one candidate per animal,
what it tells the user."""

import cv2
import numpy as np
import pytest

from dolphinfit.core.segment.auto_seed import (
    COLOUR, LONE, MIN_TILE_PX, PART, Candidate, describe, distinct, extent_px, fits_length,
    scan_order, tile_side_px,
)


def test_scan_order_starts_at_the_seed_frame_and_spreads_over_the_rest():
    assert scan_order(range(10), 3, 20) == [3, 4, 5, 6, 7, 8, 9, 2, 1, 0]
    assert scan_order(range(100), 0, 4) == [0, 1, 50, 99]
    assert scan_order([0, 8, 16, 24], 16, 3) == [16, 24, 0]


def test_extent_is_the_length_along_the_principal_axis():
    """A bar 201 px long and 21 px wide at 30°: 201 px."""
    mask = np.zeros((300, 300), np.uint8)
    box = cv2.boxPoints(((150.0, 150.0), (201.0, 21.0), 30.0))
    cv2.fillPoly(mask, [np.round(box).astype(np.int32)], 1)
    assert extent_px(mask.astype(bool)) == pytest.approx(201.0, abs=3.0)


def test_lengths_fit_the_expected_range_with_slack():
    assert fits_length(100.0, None)
    assert fits_length(65.0, (100.0, 200.0)) and not fits_length(55.0, (100.0, 200.0))
    assert fits_length(270.0, (100.0, 200.0)) and not fits_length(290.0, (100.0, 200.0))


def test_tiles_shrink_to_twice_the_longest_expected_animal():
    """Half the shorter side (1080p: 540 px) unless twice the longest animal is smaller: a
    1–4 m animal from 42 m on 720p is 22–91 px long (182-px tiles); never under
    ``MIN_TILE_PX``."""
    assert tile_side_px(1080, 1920, 0.5, None) == 540
    assert tile_side_px(1080, 1920, 0.5, (64.0, 257.0)) == 514
    assert tile_side_px(1080, 1920, 0.5, (100.0, 400.0)) == 540
    assert tile_side_px(720, 1280, 0.5, (22.0, 91.0)) == 182
    assert tile_side_px(720, 1280, 0.5, (5.0, 20.0)) == MIN_TILE_PX


def _candidate(rows: slice, cols: slice, tier: int, score: float) -> Candidate:
    mask = np.zeros((100, 200), bool)
    mask[rows, cols] = True
    return Candidate(mask, tier, score, float(cols.stop - cols.start))


def test_one_candidate_per_animal_the_best_tier_first():
    """Two looks at the same animal are one (the better tier kept, whatever its score);
    a second animal stays, and is named in the description with where it is."""
    part = _candidate(slice(10, 20), slice(10, 60), PART, 50.0)
    whole = _candidate(slice(10, 20), slice(10, 90), LONE, 10.0)
    other = _candidate(slice(60, 70), slice(100, 160), COLOUR, 30.0)
    kept = distinct([part, other, whole])
    assert kept == [whole, other]
    assert describe(kept, 7) == ("automatic seed, frame 7: 2 animals seen; took the most "
                                 "salient one at (50, 14), 80 px long; others at (130, 64)")
