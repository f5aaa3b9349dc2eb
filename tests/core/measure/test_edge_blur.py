"""The blur index of an animal's edge: rising with the blur, blind to the contrast and the
noise, NaN without an edge."""

import cv2
import numpy as np
import pytest

from dolphinfit.core.measure.edge_blur import edge_blur_px

V, U = np.mgrid[0:200, 0:300]
MASK = ((U - 150) / 100) ** 2 + ((V - 100) / 25) ** 2 <= 1   # a 50-px wide ellipse


def _ellipse(sigma: float, skin: float = 180.0, water: float = 60.0,
             noise: float = 3.0) -> np.ndarray:
    """The ellipse drawn 10× finer, averaged down (a sharp edge's pixels), blurred by σ."""
    fine_v, fine_u = np.mgrid[0:2000, 0:3000] / 10.0 + 0.05
    inside = ((fine_u - 150) / 100) ** 2 + ((fine_v - 100) / 25) ** 2 <= 1
    sharp = cv2.resize(np.where(inside, skin, water).astype(np.float32), (300, 200),
                       interpolation=cv2.INTER_AREA)
    blurred = cv2.GaussianBlur(sharp, (0, 0), sigma)
    return blurred + np.random.default_rng(0).normal(0.0, noise, blurred.shape)


def test_the_index_rises_with_the_blur_as_documented():
    readings = [edge_blur_px(_ellipse(sigma), MASK) for sigma in (0.5, 1.0, 1.5, 2.0, 3.0)]
    assert readings == pytest.approx([1.11, 1.37, 1.61, 1.79, 2.01], abs=0.01)


def test_contrast_and_colour_do_not_change_it_and_no_edge_gives_nan():
    base = edge_blur_px(_ellipse(1.0), MASK)
    assert edge_blur_px(_ellipse(1.0, skin=90.0, water=60.0), MASK) == pytest.approx(base,
                                                                                    rel=0.05)
    rgb = np.repeat(_ellipse(1.0)[..., None], 3, axis=2)
    assert edge_blur_px(rgb, MASK) == pytest.approx(base, rel=1e-6)
    assert np.isnan(edge_blur_px(_ellipse(1.0), np.zeros_like(MASK)))
    assert np.isnan(edge_blur_px(np.full((200, 300), 80.0), MASK))
