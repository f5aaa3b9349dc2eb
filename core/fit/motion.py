"""The fitted motion at any clip frame: a fit's pose interpolated between its fitted frames.

A fit poses the animal at its fitted frames only. Between two of them the position is
interpolated linearly in frame index and each part's rotation along the shorter arc at a
constant rate (spherical linear interpolation), so the animal turns and bends rather than
shrinking as blended vertices do. Before the first fitted frame, after the last, or across a
gap the fit skipped (frames without a usable mask) there is no pose: nothing is drawn there.
"""

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

# A stretch between fitted frames wider than this many times the fit's usual spacing (the
# median) is a gap: frames were dropped there, and the motion across it is unknown.
MAX_GAP_SPACINGS = 1.5


@dataclass(frozen=True)
class FramePose:
    """The fitted animal's pose at one clip frame (world frame, metres)."""

    transl: np.ndarray    # (3,) float64 root joint position, metres
    pose_aa: np.ndarray   # (M, 3) float64 axis-angle per part, radians


def bracket(frame_idx_fitted: np.ndarray, frame_idx: int) -> tuple[int, float] | None:
    """(i, w): clip frame ``frame_idx`` lies a fraction w ∈ [0, 1) of the way from fitted frame
    i to fitted frame i + 1 (w = 0 on fitted frame i itself); None outside the fitted frames
    or in a gap (MAX_GAP_SPACINGS). frame_idx_fitted: (T,) strictly increasing, T ≥ 1."""
    fitted = np.asarray(frame_idx_fitted)
    if fitted.ndim != 1 or len(fitted) == 0 or (np.diff(fitted) <= 0).any():
        raise ValueError(f"need (T,) strictly increasing fitted frames, T ≥ 1; got {fitted}")
    i = int(np.searchsorted(fitted, frame_idx, side="right")) - 1
    if i < 0 or (i == len(fitted) - 1 and frame_idx != fitted[i]):
        return None
    if frame_idx == fitted[i]:
        return i, 0.0
    span = int(fitted[i + 1] - fitted[i])
    if span > MAX_GAP_SPACINGS * np.median(np.diff(fitted)):
        return None
    return i, (frame_idx - int(fitted[i])) / span


def pose_at(frame_idx_fitted: np.ndarray, transl: np.ndarray, pose_aa: np.ndarray,
            frame_idx: int) -> FramePose | None:
    """The pose at clip frame ``frame_idx`` of a fit with transl (T, 3) and pose_aa (T, M, 3) at
    its (T,) fitted frames: a fitted frame's own, else interpolated (module doc); None where
    :func:`bracket` finds no pair of fitted frames around it."""
    transl, pose_aa = np.asarray(transl, np.float64), np.asarray(pose_aa, np.float64)
    if transl.shape != (len(frame_idx_fitted), 3) or pose_aa.shape[:1] != transl.shape[:1]:
        raise ValueError(f"need transl (T, 3) and pose_aa (T, M, 3) for the "
                         f"{len(frame_idx_fitted)} fitted frames; got {transl.shape} and "
                         f"{pose_aa.shape}")
    found = bracket(frame_idx_fitted, frame_idx)
    if found is None:
        return None
    i, weight = found
    if weight == 0.0:
        return FramePose(transl=transl[i].copy(), pose_aa=pose_aa[i].copy())
    return FramePose(transl=(1.0 - weight) * transl[i] + weight * transl[i + 1],
                     pose_aa=slerp_axis_angle(pose_aa[i], pose_aa[i + 1], weight))


def slerp_axis_angle(start: np.ndarray, end: np.ndarray, weight: float) -> np.ndarray:
    """(M, 3) rotations a fraction ``weight`` of the way from ``start`` to ``end`` (each (M, 3)
    axis-angle, radians), along the shorter arc between each pair."""
    first = Rotation.from_rotvec(start)
    step = (first.inv() * Rotation.from_rotvec(end)).as_rotvec()   # angle ≤ π: the short way
    return (first * Rotation.from_rotvec(weight * step)).as_rotvec()


@dataclass(frozen=True)
class ShownPose:
    """What the 3D view shows at a clip frame: a pose, how it was found (said to the user) and
    whether it is the fitted motion's; off the motion (before, after or in a gap of the fitted
    frames) the nearest fitted frame stands in, labelled, and nothing is drawn over the
    video."""

    pose: FramePose
    label: str
    is_on_motion: bool


def shown_pose(frame_idx_fitted: np.ndarray, transl: np.ndarray, pose_aa: np.ndarray,
               frame_idx: int) -> ShownPose:
    """The pose at clip frame ``frame_idx`` (:func:`pose_at`), else the nearest fitted frame's."""
    fitted = np.asarray(frame_idx_fitted)
    pose = pose_at(fitted, transl, pose_aa, frame_idx)
    if pose is not None:
        i = int(np.searchsorted(fitted, frame_idx, side="right")) - 1
        label = (f"fitted frame {frame_idx}" if fitted[i] == frame_idx else
                 f"between fitted frames {int(fitted[i])} and {int(fitted[i + 1])}")
        return ShownPose(pose, label, True)
    nearest = int(np.argmin(np.abs(fitted - frame_idx)))
    return ShownPose(FramePose(transl=np.asarray(transl[nearest], np.float64),
                               pose_aa=np.asarray(pose_aa[nearest], np.float64)),
                     f"nearest fitted frame {int(fitted[nearest])}", False)
