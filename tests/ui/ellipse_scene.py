"""A synthetic frame with known truth for GUI tests: 800×400 px of water with a dark
elliptical "dolphin" (centre (400, 200), semi-axes 300 × 60 px, major axis rotated by 10°), so
every length, edge and width has an analytic value."""

import numpy as np
from PySide6.QtCore import Qt

from dolphinfit.core.measure.annotation import place_stations

WIDTH, HEIGHT = 800, 400
CENTRE = np.array([400.0, 200.0])
SEMI_AXES = np.array([300.0, 60.0])
ANGLE = np.deg2rad(10.0)
MAJOR = np.array([np.cos(ANGLE), np.sin(ANGLE)])
MINOR = np.array([-np.sin(ANGLE), np.cos(ANGLE)])
# Quadratic form of the outline: (p − c)ᵀ Q (p − c) = 1
FORM = np.outer(MAJOR, MAJOR) / SEMI_AXES[0] ** 2 + np.outer(MINOR, MINOR) / SEMI_AXES[1] ** 2
WATER, SKIN = (20, 90, 120), (70, 70, 75)
VIEW_SIZE = (1200, 600)  # the frame fits at 1.5 screen px per image px
LEFT = Qt.MouseButton.LeftButton


def dolphin_mask() -> np.ndarray:
    """(H, W) bool: pixel centres inside the outline."""
    v, u = np.mgrid[0:HEIGHT, 0:WIDTH]
    rel = np.stack([u, v], axis=-1) - CENTRE
    # sum over both pixel axes of relᵢ Qᵢⱼ relⱼ
    return np.einsum("...i,ij,...j->...", rel, FORM, rel) <= 1.0


def chord(point: np.ndarray, normal: np.ndarray) -> tuple[float, float]:
    """Signed distances along ``normal`` from ``point`` to the outline: side A (> 0), side B."""
    rel = point - CENTRE
    a, b, c = normal @ FORM @ normal, 2 * rel @ FORM @ normal, rel @ FORM @ rel - 1
    root = np.sqrt(b * b - 4 * a * c)
    return (-b + root) / (2 * a), (-b - root) / (2 * a)


def analytic_widths(midline_px: np.ndarray) -> np.ndarray:
    stations = place_stations(midline_px)
    return np.array([np.subtract(*chord(p, n))
                     for p, n in zip(stations.points_px, stations.normals)])


AXIS_ENDS = CENTRE + np.outer([-SEMI_AXES[0], SEMI_AXES[0]], MAJOR)
MIDLINE = np.array([AXIS_ENDS[0], CENTRE, AXIS_ENDS[1]])


def dolphin_frame() -> np.ndarray:
    """(H, W, 3) uint8 RGB frame of the scene."""
    return np.where(dolphin_mask()[..., None], SKIN, WATER).astype(np.uint8)
