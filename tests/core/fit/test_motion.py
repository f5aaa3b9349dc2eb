"""The fitted motion between fitted frames, on hand-made poses turning about fixed axes; and
the fit's shape posed at them, against the fit's own meshes."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from dolphinfit.core.fit.motion import bracket, pose_at, shown_pose
from dolphinfit.core.fit.pose_mesh import posed_mesh

FITTED = np.array([10, 16, 22, 40])   # every 6 frames, then a gap of 18 (frames dropped)
TRANSL = np.array([[0.0, 0.0, -0.2], [0.6, 0.3, -0.4], [1.2, 0.9, -0.2], [3.0, 2.0, 0.0]])
HEADING_DEG = np.array([10.0, 50.0, 170.0, 0.0])   # the root part turns about z
BEND_RAD = np.array([0.1, 0.3, -0.1, 0.0])         # the second part bends about y


def _poses() -> np.ndarray:
    """(T, 2, 3) axis-angle: the root's heading about z, the second part's bend about y."""
    pose = np.zeros((len(FITTED), 2, 3))
    pose[:, 0, 2] = np.radians(HEADING_DEG)
    pose[:, 1, 1] = BEND_RAD
    return pose


POSE = _poses()


def test_a_fitted_frame_gives_its_own_pose():
    """On a fitted frame the pose is the fit's, unchanged."""
    pose = pose_at(FITTED, TRANSL, POSE, 16)
    np.testing.assert_array_equal(pose.transl, TRANSL[1])
    np.testing.assert_array_equal(pose.pose_aa, POSE[1])


def test_the_mid_frame_is_the_mean_of_its_neighbours():
    """Half way from 10 to 16: position, heading (10° → 50°) and bend (0.1 → 0.3) average."""
    pose = pose_at(FITTED, TRANSL, POSE, 13)
    np.testing.assert_allclose(pose.transl, (TRANSL[0] + TRANSL[1]) / 2, atol=1e-12)
    np.testing.assert_allclose(np.degrees(pose.pose_aa[0, 2]), 30.0, atol=1e-9)
    np.testing.assert_allclose(pose.pose_aa[1], [0.0, 0.2, 0.0], atol=1e-12)
    np.testing.assert_allclose(pose.pose_aa[0, :2], 0.0, atol=1e-12)


def test_a_third_of_the_way_weighs_a_third():
    """Frame 18, a third of the way from 16 to 22: heading 50° + 120°/3, bend 0.3 − 0.4/3."""
    pose = pose_at(FITTED, TRANSL, POSE, 18)
    np.testing.assert_allclose(pose.transl, TRANSL[1] + (TRANSL[2] - TRANSL[1]) / 3, atol=1e-12)
    np.testing.assert_allclose(np.degrees(pose.pose_aa[0, 2]), 90.0, atol=1e-9)
    np.testing.assert_allclose(pose.pose_aa[1, 1], 0.3 - 0.4 / 3, atol=1e-12)


def test_angles_turn_the_short_way_round():
    """From heading 170° to −170° the animal turns 20° through 180°, not 340° through 0°."""
    pose = np.zeros((2, 1, 3))
    pose[:, 0, 2] = np.radians([170.0, -170.0])
    mid = pose_at(np.array([0, 4]), np.zeros((2, 3)), pose, 1)
    angle = Rotation.from_rotvec(mid.pose_aa[0]).as_euler("ZYX", degrees=True)
    np.testing.assert_allclose(angle, [175.0, 0.0, 0.0], atol=1e-9)


@pytest.mark.parametrize("frame", [9, 0, 41, 100])
def test_outside_the_fitted_frames_there_is_no_pose(frame):
    """Before the first fitted frame and after the last: none, not the nearest one's."""
    assert pose_at(FITTED, TRANSL, POSE, frame) is None


def test_across_a_gap_there_is_no_pose():
    """22 → 40 is three times the fit's spacing of 6: frames dropped there, nothing drawn;
    its ends are fitted frames and keep their poses."""
    assert all(pose_at(FITTED, TRANSL, POSE, frame) is None for frame in range(23, 40))
    assert pose_at(FITTED, TRANSL, POSE, 40) is not None
    assert bracket(FITTED, 22) == (2, 0.0)


def test_a_single_fitted_frame_poses_only_itself():
    assert bracket(np.array([7]), 7) == (0, 0.0)
    assert bracket(np.array([7]), 8) is None


def test_mismatched_arrays_are_refused():
    with pytest.raises(ValueError, match="transl"):
        pose_at(FITTED, TRANSL[:2], POSE, 13)
    with pytest.raises(ValueError, match="increasing"):
        bracket(np.array([3, 3]), 3)


def test_the_posed_shape_is_the_fits_own_mesh_at_fitted_frames(tiny_run):
    """A fit's rest mesh and betas posed at a fitted frame's pose give its posed vertices;
    half way between two frames the mesh lies between theirs."""
    result = tiny_run[0].result
    for t in (0, len(result.frame_idx) - 1):
        pose = pose_at(result.frame_idx, result.transl, result.pose_aa, result.frame_idx[t])
        np.testing.assert_allclose(posed_mesh(result.rest_verts, result.betas, pose),
                                   result.posed_verts[t], atol=1e-9)
    first, second = (int(f) for f in result.frame_idx[:2])
    pose = pose_at(result.frame_idx, result.transl, result.pose_aa, (first + second) / 2)
    centroid = posed_mesh(result.rest_verts, result.betas, pose).mean(axis=0)
    ends = result.posed_verts[:2].mean(axis=1)
    np.testing.assert_allclose(centroid, ends.mean(axis=0), atol=0.01)


def test_the_running_fits_previews_pose_as_its_result_does(tiny_run):
    """A preview carries the pose, shape and frames that posed_mesh takes, one per frame."""
    run, reports = tiny_run
    preview = [r.preview for r in reports if r.preview is not None][-1]
    num_frames, num_parts = len(preview.frame_idx), run.result.betas.shape[0]
    assert preview.transl.shape == (num_frames, 3)
    assert preview.pose_aa.shape == (num_frames, num_parts, 3)
    pose = pose_at(preview.frame_idx, preview.transl, preview.pose_aa, preview.frame_idx[0])
    verts = posed_mesh(preview.rest_verts, preview.betas, pose)
    assert verts.shape == run.result.rest_verts.shape and np.isfinite(verts).all()


def test_the_3d_view_shows_the_motion_and_off_it_the_nearest_fitted_frame():
    """On the motion: its pose, labelled by where it lies; before the fit, after it or in a
    gap: the nearest fitted frame's pose, labelled so, and not the motion's."""
    on = shown_pose(FITTED, TRANSL, POSE, 13)
    assert on.is_on_motion and on.label == "between fitted frames 10 and 16"
    np.testing.assert_allclose(on.pose.transl, pose_at(FITTED, TRANSL, POSE, 13).transl)
    assert shown_pose(FITTED, TRANSL, POSE, 16).label == "fitted frame 16"
    before = shown_pose(FITTED, TRANSL, POSE, 0)
    assert not before.is_on_motion and before.label == f"nearest fitted frame {FITTED[0]}"
    np.testing.assert_allclose(before.pose.transl, TRANSL[0])
    after = shown_pose(FITTED, TRANSL, POSE, 1000)
    np.testing.assert_allclose(after.pose.pose_aa, POSE[-1])
