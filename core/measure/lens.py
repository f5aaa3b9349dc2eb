"""Lens distortion: a camera calibrated from images of a printed checkerboard, and measured
points taken through it to where a distortion-free (pinhole) camera would have seen them.

Wide drone lenses bend straight lines towards the frame's edges (radial distortion), so an
animal measured off-centre is measured through the bend. OpenCV's camera calibration (Zhang's
method) fits the focal lengths, principal point and the distortion coefficients k1, k2, p1,
p2 of its model to the board's corners seen in many poses (k3 held at 0: where the board does
not reach the frame's corners it trades off against k2 and bends the corners wrongly; on
synthetic boards that left the mapping 1.7 px off in a corner, 0.5 px with k3 fixed); a
calibration whose corners
lie more than ``MAX_RMS_PX`` from where the fitted model puts them, or that saw the board in
fewer than ``MIN_VIEWS`` images, is refused.

Corrected points are where the calibrated lens's own pinhole (its focal length and centre,
no distortion) would have seen them: the lens only straightens the clicks, and every later step
(lengths, widths, metres from the altitude and the camera's focal length) stays as it is. A
calibrated focal length that differs from the camera's by more than 2 % is warned about.
"""

from collections.abc import Iterable
from dataclasses import asdict, dataclass, replace
from functools import lru_cache
from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.io.json_file import read_tagged_dataclass, write_json
from dolphinfit.core.measure.annotation import Annotation
from dolphinfit.core.measure.annotation_json import AnnotationFile

FORMAT = "dolphinfit-lens"
VERSION = 1
MIN_VIEWS = 5
MAX_RMS_PX = 1.0
OFF_CENTRE_SHARE = 0.5   # of the way from the centre to the corner: past it, a warning
FOCAL_AGREEMENT = 0.02   # calibrated and stated focal lengths further apart are warned about
SUBPIXEL_CRITERIA = (cv2.TERM_CRITERIA_EPS + cv2.TERM_CRITERIA_MAX_ITER, 30, 1e-3)


@dataclass(frozen=True)
class LensModel:
    """A calibrated camera: pinhole intrinsics in pixels and OpenCV's distortion
    coefficients (k1, k2, p1, p2, k3) for images ``width_px`` × ``height_px``."""

    width_px: int
    height_px: int
    fx_px: float
    fy_px: float
    cx_px: float
    cy_px: float
    distortion: tuple[float, float, float, float, float]
    rms_px: float
    num_views: int
    source: str

    def matrix(self) -> np.ndarray:
        return np.array([[self.fx_px, 0.0, self.cx_px], [0.0, self.fy_px, self.cy_px],
                         [0.0, 0.0, 1.0]])

    def undistort(self, points_px: np.ndarray) -> np.ndarray:
        """(N, 2) points seen through this lens, where its own pinhole camera (same focal
        length and centre, no distortion) would see them; NaN points stay NaN."""
        points = np.asarray(points_px, dtype=np.float64).reshape(-1, 2)
        out = np.full_like(points, np.nan)
        finite = np.isfinite(points).all(axis=1)
        if finite.any():
            out[finite] = cv2.undistortPoints(points[finite].reshape(-1, 1, 2), self.matrix(),
                                              np.array(self.distortion),
                                              P=self.matrix()).reshape(-1, 2)
        return out

    def distort(self, points_px: np.ndarray) -> np.ndarray:
        """(N, 2) points of this lens's own pinhole camera, where the lens shows them (the
        inverse of ``undistort``)."""
        points = np.asarray(points_px, dtype=np.float64).reshape(-1, 2)
        rays = np.column_stack([(points[:, 0] - self.cx_px) / self.fx_px,
                                (points[:, 1] - self.cy_px) / self.fy_px, np.ones(len(points))])
        seen, _ = cv2.projectPoints(rays, np.zeros(3), np.zeros(3), self.matrix(),
                                    np.array(self.distortion))
        return seen.reshape(-1, 2)

    def undistort_image(self, image: np.ndarray) -> np.ndarray:
        """An (H, W[, C]) image of the calibrated size as this lens's own pinhole camera would
        have seen it (bilinear; 0 where the lens saw nothing)."""
        self.check_image_size(image.shape[1], image.shape[0], "the image")
        map_x, map_y = _undistortion_maps(self)
        return cv2.remap(image, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT)

    def undistort_mask(self, mask: np.ndarray) -> np.ndarray:
        """An (H, W) bool mask as the pinhole camera would have seen it."""
        return self.undistort_image(mask.astype(np.uint8) * 255) >= 128

    def focal_warning(self, camera: CameraIntrinsics) -> str | None:
        """A warning when the calibrated focal length is not the camera's (the lens only
        straightens the clicks; metres still come from the camera's focal length)."""
        focal = (self.fx_px + self.fy_px) / 2
        if abs(focal / camera.focal_px - 1) <= FOCAL_AGREEMENT:
            return None
        return (f"the lens calibration measured a focal length of {focal:.0f} px where the "
                f"camera says {camera.focal_px:.0f} px: check the camera preset (lengths use "
                f"the camera's)")

    def check_image_size(self, width_px: int, height_px: int, where: str) -> None:
        """InputError naming ``where`` unless the images are the calibrated size."""
        if (width_px, height_px) != (self.width_px, self.height_px):
            raise InputError(f"{where}: the lens was calibrated on {self.width_px}×"
                             f"{self.height_px} px images; these are {width_px}×{height_px} px "
                             f"(another video mode: calibrate it on its own)")

    def to_json(self) -> dict:
        return {"format": FORMAT, "version": VERSION, **asdict(self)}


@lru_cache(maxsize=4)
def _undistortion_maps(lens: LensModel) -> tuple[np.ndarray, np.ndarray]:
    """For each pixel of the pinhole image, where the image seen through ``lens`` shows it
    (OpenCV's remap tables, float32 x and y)."""
    matrix = lens.matrix()
    return cv2.initUndistortRectifyMap(matrix, np.array(lens.distortion), None, matrix,
                                       (lens.width_px, lens.height_px), cv2.CV_32FC1)


def undistorted_annotation(annotation: Annotation, lens: LensModel) -> Annotation:
    """``annotation`` with its midline clicks and edge points taken through ``lens``."""
    edges = lens.undistort(annotation.edges_px.reshape(-1, 2))
    return replace(annotation, midline_px=lens.undistort(annotation.midline_px),
                   edges_px=edges.reshape(annotation.edges_px.shape))


def through_lens(doc: AnnotationFile, lens: LensModel | None,
                 lens_name: str) -> tuple[AnnotationFile, list[str], list[str]]:
    """An annotated frame measured through ``lens`` (called ``lens_name`` in the notes):
    its clicks taken through it, with a note and a warning when the lens's focal length is
    not the camera's; without a lens, the frame as it is and a warning when it was measured
    far off-centre. InputError when the lens is of another image size. (doc, notes,
    warnings)."""
    camera = doc.calibration.camera.intrinsics()
    if lens is None:
        warning = off_centre_warning(doc.annotation, camera)
        return doc, [], [] if warning is None else [warning]
    lens.check_image_size(camera.width_px, camera.height_px, lens_name)
    warning = lens.focal_warning(camera)
    return (replace(doc, annotation=undistorted_annotation(doc.annotation, lens)),
            [f"clicks taken through {lens_name}"], [] if warning is None else [warning])


def _share_to_corner(points: np.ndarray, camera: CameraIntrinsics) -> float:
    """How far the farthest of (N, 2) points lies from the image centre, as a share of the
    distance to the corner (0 at the centre, 1 in a corner)."""
    centre = np.array([camera.cx_px, camera.cy_px])
    corner = np.hypot(camera.width_px / 2, camera.height_px / 2)
    return float(np.max(np.linalg.norm(points - centre, axis=1)) / corner)


def off_centre_share(annotation: Annotation, camera: CameraIntrinsics) -> float:
    """``_share_to_corner`` of the annotation's clicks and edge points."""
    points = np.concatenate([annotation.midline_px, annotation.edges_px.reshape(-1, 2)])
    return _share_to_corner(points[np.isfinite(points).all(axis=1)], camera)


def _off_centre_warning(share: float, done: str) -> str | None:
    if share <= OFF_CENTRE_SHARE:
        return None
    return (f"{done} {100 * share:.0f} % of the way from the frame's centre to its corner "
            f"without a lens model: lens distortion bends lengths there (`dolphinfit "
            f"calibrate lens`)")


def off_centre_warning(annotation: Annotation, camera: CameraIntrinsics) -> str | None:
    """A warning for a measurement made far off-centre without a lens model."""
    return _off_centre_warning(off_centre_share(annotation, camera), "measured")


def masks_off_centre_warning(masks: np.ndarray, camera: CameraIntrinsics) -> str | None:
    """A warning for a fit whose (T, H, W) masks reach far off-centre, made without a lens
    model (the farthest mask pixel of any frame counts)."""
    rows, cols = np.nonzero(masks.any(axis=0))
    if rows.size == 0:
        return None
    points = np.column_stack([cols, rows]).astype(np.float64)
    return _off_centre_warning(_share_to_corner(points, camera), "fitted")


def board_corners(gray: np.ndarray, board: tuple[int, int]) -> np.ndarray | None:
    """(C, 1, 2) float32 inner corners of a checkerboard of ``board`` = (columns, rows) inner
    corners, refined to a tenth of a pixel; None when the board is not found whole."""
    found, corners = cv2.findChessboardCorners(
        gray, board, flags=cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE)
    if not found:
        return None
    return cv2.cornerSubPix(gray, corners, (5, 5), (-1, -1), SUBPIXEL_CRITERIA)


def calibrate_lens(images: Iterable[np.ndarray], board: tuple[int, int], square_mm: float,
                   source: str) -> LensModel:
    """The lens of the camera that took ``images`` (RGB or grey, one size) of a checkerboard
    with ``board`` inner corners of ``square_mm`` squares; InputError when the board was found
    in fewer than MIN_VIEWS images, the images differ in size, or the fit is poor."""
    columns, rows = board
    if columns < 3 or rows < 3 or not square_mm > 0:
        raise InputError(f"--board {columns}x{rows} --square-mm {square_mm:g}: a board needs "
                         f"at least 3×3 inner corners and squares of a positive size")
    grid = np.zeros((columns * rows, 3), np.float32)
    grid[:, :2] = np.mgrid[0:columns, 0:rows].T.reshape(-1, 2) * square_mm
    object_points, image_points, size, seen = [], [], None, 0
    for image in images:
        seen += 1
        gray = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY) if image.ndim == 3 else image
        if size is not None and gray.shape[::-1] != size:
            raise InputError(f"{source}: image {seen} is {gray.shape[1]}×{gray.shape[0]} px, "
                             f"the first {size[0]}×{size[1]}: one calibration per video mode")
        size = gray.shape[::-1]
        corners = board_corners(gray, board)
        if corners is not None:
            object_points.append(grid)
            image_points.append(corners)
    if len(image_points) < MIN_VIEWS:
        raise InputError(f"{source}: the {columns}×{rows} board was found in "
                         f"{len(image_points)} of {seen} images; a calibration needs at least "
                         f"{MIN_VIEWS} views of it, tilted and spread over the frame")
    rms, matrix, distortion, _, _ = cv2.calibrateCamera(object_points, image_points, size,
                                                        None, None, flags=cv2.CALIB_FIX_K3)
    if not rms <= MAX_RMS_PX:
        raise InputError(f"{source}: the corners lie {rms:.2f} px (RMS) from the fitted lens; "
                         f"above {MAX_RMS_PX:g} px the calibration is refused (blurred or bent "
                         f"board, or the wrong --board size)")
    return LensModel(width_px=size[0], height_px=size[1], fx_px=float(matrix[0, 0]),
                     fy_px=float(matrix[1, 1]), cx_px=float(matrix[0, 2]),
                     cy_px=float(matrix[1, 2]),
                     distortion=tuple(float(d) for d in distortion.ravel()[:5]),
                     rms_px=float(rms), num_views=len(image_points), source=source)


def checked_lens(lens: LensModel, where: str) -> LensModel:
    """``lens`` if its numbers can be used; InputError naming ``where`` otherwise."""
    numbers = (lens.fx_px, lens.fy_px, lens.cx_px, lens.cy_px, *lens.distortion)
    if not (np.all(np.isfinite(numbers)) and lens.fx_px > 0 and lens.fy_px > 0
            and lens.width_px > 0 and lens.height_px > 0):
        raise InputError(f"{where}: focal lengths, image size and coefficients must be finite "
                         f"and the focal lengths and size positive")
    return lens


def read_lens(path: Path | str) -> LensModel:
    """A lens written by ``dolphinfit calibrate lens``; InputError naming the file otherwise."""
    path = Path(path)
    return checked_lens(read_tagged_dataclass(path, LensModel, FORMAT, VERSION, "lens model"),
                        str(path))


def write_lens(lens: LensModel, path: Path) -> None:
    """``path`` as JSON, written atomically."""
    write_json(path, lens.to_json())
