"""The outline fitted to the image's edge: analytic animals (coverage counted on 8 × 8 points a
pixel) under blur, contrast, noise, JPEG, glitter and a companion, from masks drawn too wide or
too narrow."""

import cv2
import numpy as np
import pytest

from dolphinfit.core.segment.evaluate import outline_offset_px
from dolphinfit.core.segment.outline_fit import refine_outline

HEIGHT, WIDTH = 150, 240
WATER = (0.10, 0.35, 0.40)
LIGHT_GREY = (0.55, 0.60, 0.62)


def coverage(grow_px: float = 0.0, width_px: float = 24.0, length_px: float = 150.0,
             angle_deg: float = 20.0, centre: tuple[float, float] = (120.3, 74.8),
             wobble_px: float = 0.0, points: int = 8) -> np.ndarray:
    """(H, W) share of each pixel inside a spindle-shaped body (pointed at both ends, a
    dolphin's outline to a first approximation) grown by ``grow_px``, its sides waved by
    ``wobble_px`` (a network's uneven outline)."""
    rows, cols = np.mgrid[0:HEIGHT * points, 0:WIDTH * points]
    x = (cols + 0.5) / points - centre[0]
    y = (rows + 0.5) / points - centre[1]
    cos, sin = np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))
    along = (cos * x + sin * y) / length_px + 0.5
    across = -sin * x + cos * y
    half = width_px / 2 * np.clip(4 * along * (1 - along), 0, None) ** 0.6
    half = half + wobble_px * np.sin(37 * along) * np.sin(11 * along + 1)
    inside = (np.abs(across) <= half + grow_px) & (along > 0) & (along < 1)
    return inside.reshape(HEIGHT, points, WIDTH, points).mean((1, 3))


TRUE_COVER = coverage()
TRUTH = TRUE_COVER >= 0.5
DRAWN_WIDE = coverage(0.7, wobble_px=0.3) >= 0.5
DRAWN_NARROW = coverage(-0.6, wobble_px=0.3) >= 0.5


def image(body=LIGHT_GREY, water=WATER, blur_px: float = 0.8, noise: float = 0.01,
          jpeg_quality: int | None = None, cover: np.ndarray = TRUE_COVER,
          seed: int = 0) -> np.ndarray:
    """(H, W, 3) uint8 RGB of the body over the water, blurred, noisy, perhaps JPEG'd."""
    rng = np.random.default_rng(seed)
    scene = cover[..., None] * np.array(body) + (1 - cover[..., None]) * np.array(water)
    if blur_px > 0:
        scene = cv2.GaussianBlur(scene.astype(np.float32), (0, 0), blur_px)
    scene = scene + rng.normal(0, noise, scene.shape)
    rgb = np.clip(scene * 255 + 0.5, 0, 255).astype(np.uint8)
    if jpeg_quality is not None:
        _ok, encoded = cv2.imencode(".jpg", rgb[..., ::-1],
                                    [cv2.IMWRITE_JPEG_QUALITY, jpeg_quality])
        rgb = cv2.imdecode(encoded, cv2.IMREAD_COLOR)[..., ::-1]
    return rgb


@pytest.mark.parametrize("drawn", [DRAWN_WIDE, DRAWN_NARROW], ids=["wide", "narrow"])
def test_the_outline_moves_to_the_edge_from_either_side(drawn):
    """A mask drawn 0.7 px too wide or 0.6 px too narrow ends within 0.05 px of the truth."""
    assert abs(outline_offset_px(drawn, TRUTH)) > 0.4
    fitted = refine_outline(image(), drawn)
    assert abs(outline_offset_px(fitted.mask, TRUTH)) < 0.05
    assert fitted.fitted_share > 0.9
    assert abs(fitted.moved_px + outline_offset_px(drawn, TRUTH)) < 0.05


@pytest.mark.parametrize("case", [
    dict(blur_px=0.3), dict(blur_px=2.0),
    dict(body=(0.13, 0.37, 0.42)),                      # 8 grey levels of contrast
    dict(body=(0.04, 0.08, 0.10), water=(0.06, 0.14, 0.18)),   # dark over dark
    dict(body=(0.80, 0.82, 0.80), water=(0.74, 0.78, 0.80)),   # light over light
    dict(noise=0.03), dict(jpeg_quality=30),
], ids=["blur 0.3", "blur 2", "contrast 8", "dark over dark", "light over light",
        "noise", "jpeg 30"])
def test_the_outline_does_not_move_with_blur_contrast_noise_or_compression(case):
    fitted = refine_outline(image(**case), DRAWN_WIDE)
    assert abs(outline_offset_px(fitted.mask, TRUTH)) < 0.1


@pytest.mark.parametrize("blur_px", [0.5, 1.0, 2.0])
def test_the_edge_blur_is_measured(blur_px):
    assert refine_outline(image(blur_px=blur_px, noise=0.0), DRAWN_WIDE).blur_px == \
        pytest.approx(blur_px, abs=0.2)


def test_glitter_and_a_companion_do_not_pull_the_outline():
    """White specks of sun glitter in the water near the flanks and a second animal 4 px off
    one side leave the outline within 0.1 px."""
    companion = coverage(angle_deg=20.0, centre=(131.3, 45.0), width_px=20.0)
    scene = image(cover=np.clip(TRUE_COVER + companion, 0, 1)).copy()
    rng = np.random.default_rng(3)
    near = cv2.dilate(TRUTH.astype(np.uint8), np.ones((9, 9), np.uint8)).astype(bool) & ~TRUTH
    specks = np.flatnonzero(near.ravel())
    scene.reshape(-1, 3)[rng.choice(specks, len(specks) // 25, replace=False)] = 250
    fitted = refine_outline(scene, DRAWN_WIDE)
    assert abs(outline_offset_px(fitted.mask, TRUTH)) < 0.1


def test_without_an_edge_the_mask_stays_as_drawn():
    flat = np.full((HEIGHT, WIDTH, 3), 90, np.uint8)
    fitted = refine_outline(flat, DRAWN_WIDE)
    assert np.array_equal(fitted.mask, DRAWN_WIDE)
    assert fitted.fitted_share == 0.0
    assert np.isnan(fitted.blur_px)


def test_a_mask_cut_by_the_window_keeps_its_cut_side():
    """The body runs out of the window on the left: the cut side stays where it is, the
    flanks move to the edge."""
    cut = slice(60, None)
    fitted = refine_outline(image()[:, cut], DRAWN_WIDE[:, cut])
    assert fitted.mask[:, 0].sum() == pytest.approx(TRUTH[:, cut][:, 0].sum(), abs=2)
    assert abs(outline_offset_px(fitted.mask, TRUTH[:, cut])) < 0.1
