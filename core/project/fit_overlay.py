"""The fitted mesh's silhouette on a video frame, as outlines in image pixels.

Straight nadir projection (DESIGN.md §3, core/camera.py): a world point (x, y, z) of frame t
lands at u = cx + f·x / (h − z), v = cy − f·y / (h − z), h the frame's altitude. The projected
triangles are filled into a mask over their bounding box and its outer contours traced, so
the outline is the silhouette's, fins included. Refraction is not applied: parts under water
are drawn where a straight line of sight would put them.
"""

import cv2
import numpy as np

from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.project.mask_store import outlines

MARGIN_PX = 2


def project_straight(verts: np.ndarray, intrinsics: CameraIntrinsics,
                     altitude_m: float) -> np.ndarray:
    """(V, 2) pixel positions (u, v) of world points (V, 3) seen from ``altitude_m``."""
    depth = altitude_m - verts[:, 2]
    u = intrinsics.cx_px + intrinsics.focal_px * verts[:, 0] / depth
    v = intrinsics.cy_px - intrinsics.focal_px * verts[:, 1] / depth
    return np.stack([u, v], axis=1)


def silhouette_outlines(verts: np.ndarray, faces: np.ndarray, intrinsics: CameraIntrinsics,
                        altitude_m: float) -> list[np.ndarray]:
    """Outer outlines (each (N, 2) pixels, u right, v down) of the mesh's silhouette."""
    if not altitude_m > verts[:, 2].max():
        raise ValueError(f"the camera at {altitude_m} m is not above the fitted mesh")
    uv = project_straight(verts, intrinsics, altitude_m)
    origin = np.floor(uv.min(axis=0)) - MARGIN_PX
    size = (np.ceil(uv.max(axis=0)) - origin + MARGIN_PX).astype(int)
    mask = np.zeros((size[1], size[0]), np.uint8)
    # pixel centres at integers: fillPoly's integer vertices with 4 fractional bits
    triangles = np.round((uv[faces] - origin) * 16).astype(np.int32)
    cv2.fillPoly(mask, list(triangles), 255, lineType=cv2.LINE_8, shift=4)
    return [outline + origin for outline in outlines(mask)]
