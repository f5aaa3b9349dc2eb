"""How blurred an animal's edge is in an image: a blur index in pixels.

For a step of contrast C blurred by a Gaussian of σ, the steepest slope across the edge is
C / (σ √(2π)). Here C is the difference of the mean grey level just inside and just outside the
mask's outline (1–3 px from it), and the slope the upper quartile of the gradient along the
outline, lightly smoothed so that noise does not pass for sharpness. The rings lie within the
blur of a soft edge and the smoothing adds its own, so the index is σ only roughly: on an ellipse
blurred by σ = 0.5, 1, 1.5, 2 and 3 px it reads 1.11, 1.37, 1.61, 1.79 and 2.01 (rising, but
compressed; tests/core/measure/test_edge_blur.py). An outline drawn by a segmenter cannot be
placed more finely than the edge is sharp: the fit's intervals take the outline's SD in
proportion to this index where that is the larger error (core.measure.fit_uncertainty).
"""

import cv2
import numpy as np

RING_PX = (1, 3)            # inside: eroded 1, not eroded 3; outside: dilated 4, not dilated 2
GRADIENT_SMOOTH_PX = 0.7
SLOPE_QUANTILE = 75


def _grey(image: np.ndarray) -> np.ndarray:
    image = np.asarray(image, dtype=np.float32)
    if image.ndim == 3:
        image = cv2.cvtColor(image, cv2.COLOR_RGB2GRAY)
    return image


def edge_blur_px(image: np.ndarray, mask: np.ndarray) -> float:
    """σ in pixels of the edge between ``mask`` (H, W; non-zero = animal) and the water around
    it in ``image`` (H, W) or (H, W, 3), any scale; NaN where the mask is empty or the edge
    shows no contrast."""
    grey, region = _grey(image), (np.asarray(mask) != 0).astype(np.uint8)
    if not region.any():
        return float("nan")
    kernel = np.ones((3, 3), np.uint8)
    inside = (cv2.erode(region, kernel, iterations=RING_PX[0]).astype(bool)
              & ~cv2.erode(region, kernel, iterations=RING_PX[1]).astype(bool))
    outside = (cv2.dilate(region, kernel, iterations=RING_PX[1] + 1).astype(bool)
               & ~cv2.dilate(region, kernel, iterations=RING_PX[0] + 1).astype(bool))
    outline = (cv2.dilate(region, kernel) - cv2.erode(region, kernel)).astype(bool)
    if not (inside.any() and outside.any()):
        return float("nan")
    contrast = abs(float(grey[inside].mean()) - float(grey[outside].mean()))
    smooth = cv2.GaussianBlur(grey, (0, 0), GRADIENT_SMOOTH_PX)
    slope = np.hypot(cv2.Sobel(smooth, cv2.CV_32F, 1, 0, ksize=3),
                     cv2.Sobel(smooth, cv2.CV_32F, 0, 1, ksize=3)) / 8.0
    steepest = float(np.percentile(slope[outline], SLOPE_QUANTILE))
    if contrast <= 0 or steepest <= 0:
        return float("nan")
    return contrast / (np.sqrt(2 * np.pi) * steepest)
