"""The trackers' mask operations, done in the mask's box, against OpenCV's on the whole
frame: the same to the bit."""

import cv2
import numpy as np
import pytest

from dolphinfit.core.segment.regions import centroid
from dolphinfit.core.segment.seed import DISTANCE_FROM_PX, dilate


def random_mask(seed: int, least_parts: int = 0) -> np.ndarray:
    """A frame of 5–200 px a side with up to three rectangles, at its edges too."""
    rng = np.random.default_rng(seed)
    height, width = (int(v) for v in rng.integers(5, 200, 2))
    mask = np.zeros((height, width), bool)
    for _ in range(int(rng.integers(least_parts, 4))):
        row, col = int(rng.integers(0, height)), int(rng.integers(0, width))
        mask[row:row + int(rng.integers(1, 30)), col:col + int(rng.integers(1, 30))] = True
    return mask


@pytest.mark.parametrize("seed", range(40))
def test_dilate_equals_a_whole_frame_dilation(seed):
    """Dilating only the mask's box grown by the radius is exactly the whole frame's
    dilation, at the frame's edges too, and empty for an empty mask."""
    mask = random_mask(seed)
    rng = np.random.default_rng(seed)
    radius = int(rng.integers(0, 2 * DISTANCE_FROM_PX))
    np.testing.assert_array_equal(dilate(mask, radius), _whole_frame_dilation(mask, radius))


def _whole_frame_dilation(mask: np.ndarray, radius: int) -> np.ndarray:
    """The whole frame dilated by OpenCV's disc kernel, or from ``DISTANCE_FROM_PX`` by the
    Euclidean distance to the mask (all beyond it when the mask is empty)."""
    if radius < DISTANCE_FROM_PX:
        kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1))
        return cv2.dilate(mask.astype(np.uint8), kernel).astype(bool)
    if not mask.any():
        return mask
    distance = cv2.distanceTransform((~mask).astype(np.uint8), cv2.DIST_L2,
                                     cv2.DIST_MASK_PRECISE)
    return distance <= radius


@pytest.mark.parametrize("radius", [DISTANCE_FROM_PX, 50, 100])
def test_a_large_dilation_by_distance_is_the_kernels_disc_but_at_its_rim(radius):
    """From ``DISTANCE_FROM_PX`` the distance transform grows a body-shaped mask as the disc
    kernel would, but for a one-pixel rim: under 1 % of the grown pixels differ."""
    mask = np.zeros((800, 800), np.uint8)
    cv2.ellipse(mask, (400, 400), (200, 40), 30, 0, 360, 1, -1)
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1))
    by_kernel = cv2.dilate(mask, kernel).astype(bool)
    grown = dilate(mask.astype(bool), radius)
    assert np.count_nonzero(grown ^ by_kernel) < 0.01 * np.count_nonzero(by_kernel)


@pytest.mark.parametrize("seed", range(40))
def test_centroid_equals_the_whole_frames_moments(seed):
    mask = random_mask(seed, least_parts=1)
    moments = cv2.moments(mask.astype(np.uint8), binaryImage=True)
    expected = np.array([moments["m10"], moments["m01"]]) / moments["m00"]
    np.testing.assert_array_equal(centroid(mask), expected)
