"""Lens distortion: coefficients recovered from checkerboards rendered through a known lens,
poor calibrations refused, and an animal measured at the frame's centre and in its corner
agreeing once its clicks are taken through the lens."""

import cv2
import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.measure.annotation import Annotation, pixel_measurements
from dolphinfit.core.measure.lens import (
    LensModel,
    calibrate_lens,
    masks_off_centre_warning,
    off_centre_warning,
    read_lens,
    undistorted_annotation,
    write_lens,
)
from dolphinfit.core.measure.stations import NUM_STATIONS

WIDTH, HEIGHT = 1280, 720
MATRIX = np.array([[900.0, 0.0, 639.5], [0.0, 900.0, 359.5], [0.0, 0.0, 1.0]])
DISTORTION = np.array([-0.12, 0.05, 0.0, 0.0, 0.0])   # barrel, as wide drone lenses bend
BOARD, SQUARE_MM, TEXTURE_PX = (9, 6), 30.0, 40
PINHOLE = CameraIntrinsics(900.0, 639.5, 359.5, WIDTH, HEIGHT)


def _to_ideal_map() -> np.ndarray:
    """(H, W, 2): for each pixel of the distorted image, where the pinhole image has it."""
    v, u = np.mgrid[0:HEIGHT, 0:WIDTH]
    pixels = np.stack([u, v], -1).reshape(-1, 1, 2).astype(np.float64)
    return cv2.undistortPoints(pixels, MATRIX, DISTORTION, P=MATRIX).reshape(
        HEIGHT, WIDTH, 2).astype(np.float32)


def board_views(blur: float = 0.0) -> list[np.ndarray]:
    """Nine tilted views of the board spread over the frame, seen through the lens."""
    columns, rows = BOARD
    texture = np.full(((rows + 3) * TEXTURE_PX, (columns + 3) * TEXTURE_PX), 255, np.uint8)
    for r in range(rows + 1):
        for c in range(columns + 1):
            if (r + c) % 2 == 0:
                texture[(r + 1) * TEXTURE_PX:(r + 2) * TEXTURE_PX,
                        (c + 1) * TEXTURE_PX:(c + 2) * TEXTURE_PX] = 0
    texture_to_mm = np.array([[SQUARE_MM / TEXTURE_PX, 0, -2 * SQUARE_MM],
                              [0, SQUARE_MM / TEXTURE_PX, -2 * SQUARE_MM], [0, 0, 1]])
    to_ideal = _to_ideal_map()
    rng = np.random.default_rng(0)
    views = []
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            rotation, _ = cv2.Rodrigues(rng.normal(0.0, 0.25, 3))
            shift = np.array([-120.0 + 170.0 * dx, -75.0 + 110.0 * dy, 520.0])
            homography = MATRIX @ np.column_stack([rotation[:, 0], rotation[:, 1], shift])
            ideal = cv2.warpPerspective(texture, homography @ texture_to_mm, (WIDTH, HEIGHT),
                                        borderValue=128)
            view = cv2.remap(ideal, to_ideal[..., 0], to_ideal[..., 1], cv2.INTER_LINEAR,
                             borderValue=128)
            views.append(cv2.GaussianBlur(view, (0, 0), blur) if blur else view)
    return views


@pytest.fixture(scope="module")
def lens():
    return calibrate_lens(board_views(), BOARD, SQUARE_MM, "synthetic boards")


def test_known_coefficients_are_recovered(lens):
    """k1 to 0.003, k2 to 0.005, the principal point to 1 px, the corners 0.1 px off; the
    fitted lens puts every point of the frame within 0.6 px of where the true one does."""
    k1, k2, p1, p2, k3 = lens.distortion
    assert k1 == pytest.approx(-0.12, abs=3e-3) and k2 == pytest.approx(0.05, abs=5e-3)
    assert abs(p1) < 1e-3 and abs(p2) < 1e-3 and k3 == 0.0
    assert (lens.cx_px, lens.cy_px) == pytest.approx((639.5, 359.5), abs=1.0)
    assert lens.rms_px < 0.1 and lens.num_views >= 8
    grid = np.stack(np.meshgrid(np.linspace(0, WIDTH - 1, 17), np.linspace(0, HEIGHT - 1, 9)),
                    -1).reshape(-1, 2)
    truth = cv2.undistortPoints(grid.reshape(-1, 1, 2), MATRIX, DISTORTION, P=MATRIX)
    assert np.abs(lens.undistort(grid) - truth.reshape(-1, 2)).max() < 0.6


def test_written_lens_reads_back_equal(lens, tmp_path):
    write_lens(lens, tmp_path / "lens.json")
    assert read_lens(tmp_path / "lens.json") == lens


def test_too_few_views_and_a_poor_fit_are_refused():
    views = board_views()
    with pytest.raises(InputError, match="found in 3 of 3 images; .* at least 5"):
        calibrate_lens(views[:3], BOARD, SQUARE_MM, "three")
    with pytest.raises(InputError, match="wrong --board size|found in 0 of 9"):
        calibrate_lens(views, (8, 6), SQUARE_MM, "wrong board")


def _seen_through_lens(points: np.ndarray) -> np.ndarray:
    """Pinhole pixels → where the distorted image shows them."""
    rays = (points - MATRIX[:2, 2]) / 900.0
    ray3 = np.column_stack([rays, np.ones(len(rays))]).astype(np.float64)
    seen, _ = cv2.projectPoints(ray3, np.zeros(3), np.zeros(3), MATRIX, DISTORTION)
    return seen.reshape(-1, 2)


def _straight_animal(centre: np.ndarray, length_px: float = 300.0) -> Annotation:
    """A straight animal along u, clicked through the lens: 5 midline clicks, no widths."""
    along = centre + np.outer(np.linspace(-0.5, 0.5, 5) * length_px, [1.0, 0.0])
    return Annotation(0, _seen_through_lens(along), np.full((NUM_STATIONS, 2, 2), np.nan))


def test_an_animal_in_the_corner_measures_as_at_the_centre_once_corrected(lens):
    """300 px of animal: 299.0 px at the centre as clicked, 279.6 px in the corner (6.8 %
    short); both 300 px to 0.2 % through the fitted lens. Only the corner one (79 % of the way
    to the corner) is warned about."""
    centre, corner = _straight_animal(np.array([640.0, 360.0])), \
        _straight_animal(np.array([1050.0, 600.0]))
    raw = [pixel_measurements(a).length_px for a in (centre, corner)]
    assert raw[0] == pytest.approx(300.0, rel=5e-3) and raw[1] < 0.95 * 300.0
    fixed = [pixel_measurements(undistorted_annotation(a, lens)).length_px
             for a in (centre, corner)]
    assert fixed == pytest.approx([300.0, 300.0], rel=2e-3)
    corner_clicks = _seen_through_lens(np.array([[1050.0, 600.0], [900.0, 100.0]]))
    lens_itself = LensModel(WIDTH, HEIGHT, 900.0, 900.0, 639.5, 359.5, tuple(DISTORTION), 0.0,
                            9, "true")
    np.testing.assert_allclose(lens_itself.distort(lens_itself.undistort(corner_clicks)),
                               corner_clicks, atol=1e-3)   # distort inverts undistort
    assert off_centre_warning(centre, PINHOLE) is None
    assert "without a lens model" in off_centre_warning(corner, PINHOLE)
    assert lens.focal_warning(PINHOLE) is None
    assert "focal length of 900 px where the camera says 1000" in lens.focal_warning(
        CameraIntrinsics(1000.0, 639.5, 359.5, WIDTH, HEIGHT))


def test_a_mask_seen_through_the_lens_comes_back_undistorted():
    """An ellipse seen through the barrel lens in the frame's corner, undistorted by the
    lens's model: IoU 0.998 with the pinhole ellipse (0.825 as seen). Fitted there without a
    lens model, it is warned about; at the centre it is not."""
    lens = LensModel(WIDTH, HEIGHT, 900.0, 900.0, 639.5, 359.5, tuple(DISTORTION), 0.0, 9, "true")
    truth = np.zeros((HEIGHT, WIDTH), np.uint8)
    cv2.ellipse(truth, (1060, 600), (150, 30), 20, 0, 360, 255, -1)
    to_ideal = _to_ideal_map()
    seen = cv2.remap(truth, to_ideal[..., 0], to_ideal[..., 1], cv2.INTER_LINEAR) >= 128
    fixed, truth = lens.undistort_mask(seen), truth > 0

    def iou(a, b):
        return (a & b).sum() / (a | b).sum()
    assert iou(seen, truth) < 0.85 and iou(fixed, truth) > 0.995
    assert "fitted 8" in masks_off_centre_warning(seen[None], PINHOLE)
    centred = np.roll(seen, (-240, -420), axis=(0, 1))
    assert masks_off_centre_warning(centred[None], PINHOLE) is None
