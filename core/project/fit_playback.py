"""The fitted mesh at any clip frame, for playback: fitted frames exactly, others interpolated."""

import numpy as np


def posed_at(frame_idx_fitted: np.ndarray, posed_verts: np.ndarray,
             frame_idx: int) -> tuple[np.ndarray, str]:
    """Vertices (V, 3) of the fitted mesh at clip frame ``frame_idx`` and a label saying how.

    frame_idx_fitted: (T,) strictly increasing clip frame indices of the fitted frames;
    posed_verts: (T, V, 3). A fitted frame gives its own vertices; a frame between two fitted
    ones, the vertices interpolated linearly in frame index; a frame outside their range, the
    nearest fitted frame's vertices. The label is shown to the user.
    """
    fitted = np.asarray(frame_idx_fitted)
    verts = np.asarray(posed_verts)
    if fitted.ndim != 1 or len(fitted) == 0 or verts.shape[0] != len(fitted):
        raise ValueError(f"need (T,) fitted frames and (T, V, 3) vertices with T ≥ 1, got "
                         f"{fitted.shape} and {verts.shape}")
    if (np.diff(fitted) <= 0).any():
        raise ValueError("fitted frame indices must be strictly increasing")
    i = int(np.searchsorted(fitted, frame_idx))
    if i < len(fitted) and fitted[i] == frame_idx:
        return verts[i], f"fitted frame {frame_idx}"
    if i == 0 or i == len(fitted):
        nearest = 0 if i == 0 else len(fitted) - 1
        return verts[nearest], f"nearest fitted frame {int(fitted[nearest])}"
    before, after = int(fitted[i - 1]), int(fitted[i])
    weight = (frame_idx - before) / (after - before)
    blended = (1.0 - weight) * verts[i - 1] + weight * verts[i]
    return blended, f"interpolated between frames {before} and {after}"
