"""Fitted-mesh playback on a hand-made 3-frame fit: exact, interpolated and nearest frames."""

import numpy as np
import pytest

from dolphinfit.core.project.fit_playback import posed_at

FITTED = np.array([10, 20, 40])
# Two vertices; frame t's mesh is translated by t metres along x
BASE = np.array([[0.0, 0.0, 0.0], [1.0, 0.5, -0.2]])
POSED = np.stack([BASE + [t, 0.0, 0.0] for t in (0.0, 1.0, 3.0)])


def test_a_fitted_frame_gives_its_own_vertices():
    verts, label = posed_at(FITTED, POSED, 20)
    np.testing.assert_array_equal(verts, POSED[1])
    assert label == "fitted frame 20"


@pytest.mark.parametrize("frame, shift_m, label", [
    (15, 0.5, "interpolated between frames 10 and 20"),
    (25, 1.5, "interpolated between frames 20 and 40"),
    (35, 2.5, "interpolated between frames 20 and 40"),
])
def test_frames_between_fitted_ones_are_interpolated(frame, shift_m, label):
    verts, got = posed_at(FITTED, POSED, frame)
    np.testing.assert_allclose(verts, BASE + [shift_m, 0.0, 0.0], atol=1e-12)
    assert got == label


@pytest.mark.parametrize("frame, index, label", [(0, 0, "nearest fitted frame 10"),
                                                 (9, 0, "nearest fitted frame 10"),
                                                 (41, 2, "nearest fitted frame 40")])
def test_frames_outside_the_fit_take_the_nearest_fitted_frame(frame, index, label):
    verts, got = posed_at(FITTED, POSED, frame)
    np.testing.assert_array_equal(verts, POSED[index])
    assert got == label


def test_a_single_fitted_frame_serves_every_frame():
    verts, label = posed_at(FITTED[:1], POSED[:1], 99)
    np.testing.assert_array_equal(verts, POSED[0])
    assert label == "nearest fitted frame 10"


@pytest.mark.parametrize("fitted, posed", [(np.array([10, 10, 40]), POSED),
                                           (np.array([20, 10, 40]), POSED),
                                           (FITTED[:2], POSED),
                                           (FITTED[:0], POSED[:0])])
def test_bad_inputs_are_refused(fitted, posed):
    with pytest.raises(ValueError):
        posed_at(fitted, posed, 15)
