"""The midline and widths a mask suggests, on outlines drawn with a known midline: straight
and bent bodies with swept flukes and a notch, and flippers beside the body."""

import cv2
import numpy as np
import pytest

from dolphinfit.core.measure.annotation import place_stations, station_widths, suggest_edges
from dolphinfit.core.measure.mask_midline import annotation_from_mask, midline_from_mask

SUPERSAMPLE = 8


def _midline(length: float, curvature: float, steps: int = 400) -> tuple[np.ndarray, ...]:
    """Points, unit tangents and normals of an arc of ``length`` (px) and ``curvature``
    (1/px) from (0, 0) heading +x."""
    s = np.linspace(0.0, length, steps)
    angle = curvature * s
    if curvature:
        points = np.stack([np.sin(angle), 1 - np.cos(angle)], 1) / curvature
    else:
        points = np.stack([s, np.zeros_like(s)], 1)
    tangents = np.stack([np.cos(angle), np.sin(angle)], 1)
    return points, tangents, np.stack([-tangents[:, 1], tangents[:, 0]], 1)


def dolphin_outline(length: float, curvature: float = 0.0, sweep: float = 0.08,
                    flipper_at: float | None = None) -> np.ndarray:
    """(P, 2) outline of a body along an arc, rostrum at (0, 0), fluke notch at the arc's
    end, flukes spanning 0.26 × length with their tips ``sweep`` × length behind the notch;
    flippers 0.12 × length long and 0.02 wide at ``flipper_at`` of the length."""
    points, tangents, normals = _midline(length, curvature)
    x = np.linspace(0.0, 1.0, len(points))
    half = 0.09 * length * np.sin(np.pi * np.clip(x, 0, 1)) ** 0.6 * (1 - 0.7 * x ** 2)
    half = np.maximum(half, 0.015 * length * (x > 0.5))
    end, along, side = points[-1], tangents[-1], normals[-1]
    lobe = [end - 0.06 * length * along + 0.015 * length * side,
            end + sweep * length * along + 0.13 * length * side,
            end + 0.7 * sweep * length * along + 0.115 * length * side, end]
    mirrored = [end + (p - end) @ along * along - (p - end) @ side * side for p in lobe]
    body_end = x < 1 - 0.06
    upper = points[body_end] + half[body_end, None] * normals[body_end]
    lower = points[body_end] - half[body_end, None] * normals[body_end]
    outline = np.concatenate([upper, lobe, mirrored[::-1][1:], lower[::-1]])
    if flipper_at is None:
        return outline
    k = int(flipper_at * (len(points) - 1))
    base, out = points[k], normals[k]
    flipper = []
    for sign in (1.0, -1.0):
        root = base + sign * half[k] * 0.8 * out
        flipper.append([root - 0.01 * length * tangents[k], root + sign * 0.12 * length * out
                        + 0.03 * length * tangents[k], root + 0.01 * length * tangents[k]])
    return outline, np.array(flipper)


def rasterised(polygons: list[np.ndarray], shape: tuple[int, int],
               offset: np.ndarray) -> np.ndarray:
    """(H, W) bool: pixels more than half covered by the polygons (filled at 8×)."""
    fine = np.zeros((shape[0] * SUPERSAMPLE, shape[1] * SUPERSAMPLE), np.uint8)
    for polygon in polygons:
        corners = ((polygon + offset + 0.5) * SUPERSAMPLE - 0.5) * 4
        cv2.fillPoly(fine, [np.round(corners).astype(np.int32)], 255, shift=2)
    return cv2.resize(fine, shape[::-1], interpolation=cv2.INTER_AREA) >= 128


@pytest.mark.parametrize("length", [60.0, 170.0, 600.0])
def test_the_midline_ends_at_the_notch_not_at_the_fluke_tips(length):
    """Flukes swept back 8 % of the length behind the notch: the suggested midline runs
    rostrum tip to notch within a pixel, its length within 1 % (the tips would add 8 %)."""
    offset = np.array([20.0, 0.3 * length + 20])
    mask = rasterised([dolphin_outline(length)], (int(0.6 * length) + 40, int(1.2 * length) + 40),
                      offset)
    midline = midline_from_mask(mask)
    np.testing.assert_allclose(midline[0], offset, atol=1.0)
    np.testing.assert_allclose(midline[-1], offset + [length, 0.0], atol=1.0)
    assert place_stations(midline).length_px == pytest.approx(length, rel=0.01)


def test_a_bent_body_keeps_its_midline_along_the_body():
    """A body bent along an arc of 40° over its length: the midline's length is the arc's
    within 1 %, and its middle points lie on the arc within 2 px (a straight axis would
    miss the middle by 0.04 × length)."""
    length, curvature = 400.0, np.radians(40) / 400.0
    offset = np.array([30.0, 60.0])
    mask = rasterised([dolphin_outline(length, curvature)], (420, 480), offset)
    midline = midline_from_mask(mask, num_points=9)
    assert place_stations(midline).length_px == pytest.approx(length, rel=0.01)
    arc, _, _ = _midline(length, curvature, 4001)
    gaps = np.min(np.linalg.norm(midline[1:-1, None] - (arc + offset)[None], axis=2), axis=1)
    assert gaps.max() < 2.0


def test_a_hint_at_the_head_sets_the_direction():
    """Without a hint the narrower end is the rostrum; a point near the other end turns the
    midline round."""
    offset = np.array([20.0, 80.0])
    mask = rasterised([dolphin_outline(200.0)], (160, 280), offset)
    assert midline_from_mask(mask)[0][0] < 30
    assert midline_from_mask(mask, head_near=offset + [230.0, 0.0])[0][0] > 200


def test_flipper_stations_measure_the_body_not_the_flipper_tips():
    """Flippers at 30 % of a 300-px body: the suggested widths at 25–35 % are the body's
    (within 1.5 px), while edges walked out along the perpendicular run into the flippers."""
    length, offset = 300.0, np.array([20.0, 110.0])
    body, flippers = dolphin_outline(length, flipper_at=0.3)
    shape = (220, 380)
    plain = rasterised([body], shape, offset)
    with_flippers = rasterised([body, *flippers], shape, offset)
    stations = place_stations(midline_from_mask(plain))
    body_widths = station_widths(stations, annotation_from_mask(plain).edges_px)
    suggested = annotation_from_mask(with_flippers)
    widths = station_widths(place_stations(suggested.midline_px), suggested.edges_px)
    np.testing.assert_allclose(widths[4:7], body_widths[4:7], atol=1.5)
    walked = station_widths(stations, suggest_edges(with_flippers, stations))
    assert walked[5] > body_widths[5] + 10
