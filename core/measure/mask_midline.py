"""A suggested length midline from a dolphin's mask, for the user to review and adjust.

Seen from above, the body is long and nearly straight, so its principal axis orders the
pixels from one end to the other; each midline point is the middle of the mask's cross-section
at equal steps along that axis. The ends are told apart by their width: the flukes span about
a quarter of the body length while the rostrum is a few centimetres across, so the narrower
end is the rostrum. The far end is where the fluke tips reach, a little behind the notch: the
user moves the last point onto the notch.
"""

import numpy as np

from core.measure.annotation import Annotation, place_stations, suggest_edges

END_FRACTION = 0.06   # share of the body whose cross-section width tells the ends apart
SLICE_HALF_PX = 1.0   # pixels within this distance of a cross-section belong to it


def _cross_section_centre(along: np.ndarray, across: np.ndarray, at: float) -> float | None:
    sel = np.abs(along - at) <= SLICE_HALF_PX
    if not sel.any():
        return None
    return float((across[sel].min() + across[sel].max()) / 2)


def midline_from_mask(mask: np.ndarray, num_points: int = 7) -> np.ndarray:
    """(num_points, 2) midline (u, v) from the rostrum end to the fluke end of ``mask``.

    mask: (H, W) bool, True = dolphin. Raises ValueError when the mask is (nearly) empty.
    """
    v, u = np.nonzero(mask)
    if u.size < 20:
        raise ValueError("the mask holds no dolphin")
    points = np.stack([u, v], axis=1).astype(np.float64)
    centre = points.mean(axis=0)
    _, _, axes = np.linalg.svd(points - centre, full_matrices=False)
    axis, normal = axes[0], np.array([-axes[0][1], axes[0][0]])
    along, across = (points - centre) @ axis, (points - centre) @ normal
    low, high = along.min(), along.max()
    span = END_FRACTION * (high - low)
    widths = [np.ptp(across[along <= low + span]), np.ptp(across[along >= high - span])]
    stations = np.linspace(low, high, num_points)
    if widths[0] > widths[1]:   # the low end is the flukes: run from the other end
        stations = stations[::-1]
    midline = []
    for at in stations:
        inward = min(max(at, low + SLICE_HALF_PX), high - SLICE_HALF_PX)
        offset = _cross_section_centre(along, across, inward)
        if offset is not None:
            midline.append(centre + at * axis + offset * normal)
    return np.asarray(midline)


def annotation_from_mask(mask: np.ndarray, frame_idx: int = 0) -> Annotation:
    """The length midline and the 19 widths that a mask suggests, as "suggest edges" places
    them in the app; nobody has reviewed them."""
    midline = midline_from_mask(mask)
    return Annotation(frame_idx=frame_idx, midline_px=midline,
                      edges_px=suggest_edges(mask, place_stations(midline)))
