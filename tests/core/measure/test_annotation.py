"""Midline spline, stations, perpendicular widths, mirror mode, mask edges and calibration."""

import math

import numpy as np
import pytest

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.measure.annotation import (
    Annotation, Calibration, Geometry, midline_spline, pixel_measurements, place_stations,
    station_widths, suggest_edges,
)
from dolphinfit.core.measure.stations import STATION_FRACTIONS

NO_EDGES = np.full((19, 2, 2), np.nan)


def _edges(stations, half_widths_a, half_widths_b, along_px=0.0):
    """(S, 2, 2) edge points at given distances on sides A and B, shifted along the body."""
    tangents = np.stack([stations.normals[:, 1], -stations.normals[:, 0]], axis=1)
    base = stations.points_px + along_px * tangents
    return np.stack([base + half_widths_a[:, None] * stations.normals,
                     base - half_widths_b[:, None] * stations.normals], axis=1)


def test_straight_midline_stations_at_equal_steps():
    """Two clicks 500 px apart: length 500, stations every 25 px, normals perpendicular."""
    clicks = np.array([[100.0, 200.0], [500.0, 500.0]])
    stations = place_stations(clicks)
    assert stations.length_px == pytest.approx(500.0, rel=1e-12)
    expected = clicks[0] + STATION_FRACTIONS[:, None] * (clicks[1] - clicks[0])
    np.testing.assert_allclose(stations.points_px, expected, atol=1e-9)
    np.testing.assert_allclose(stations.normals, np.tile([-0.6, 0.8], (19, 1)), atol=1e-12)


def test_spline_passes_through_every_click():
    """The midline interpolates: it hits each click at its chord-length parameter."""
    clicks = np.array([[0.0, 0.0], [120.0, 40.0], [260.0, 50.0], [400.0, 10.0], [520.0, -60.0]])
    spline = midline_spline(clicks)
    np.testing.assert_allclose(spline(spline.x), clicks, atol=1e-9)


def test_circular_arc_length_and_equal_arc_stations():
    """Seven clicks on a quarter circle of radius R = 800 px: length 400π and stations on
    the circle at equal angles, within the cubic's interpolation error (5/384)·h⁴/R³ ≈ 0.05 px
    for h = 209 px chords (twice that near the not-a-knot ends)."""
    radius, angles = 800.0, np.linspace(0.0, math.pi / 2, 7)
    clicks = radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    stations = place_stations(clicks)
    assert stations.length_px == pytest.approx(radius * math.pi / 2, abs=0.05)
    np.testing.assert_allclose(np.linalg.norm(stations.points_px, axis=1), radius, atol=0.15)
    station_angles = np.arctan2(stations.points_px[:, 1], stations.points_px[:, 0])
    np.testing.assert_allclose(station_angles * radius, STATION_FRACTIONS * math.pi / 2 * radius,
                               atol=0.05)
    radial = stations.points_px / np.linalg.norm(stations.points_px, axis=1, keepdims=True)
    np.testing.assert_allclose(np.abs(np.sum(stations.normals * radial, axis=1)), 1, atol=1e-4)


def test_reversed_clicks_give_the_same_stations_and_widths():
    """Clicking notch → rostrum yields the same stations in reverse (MorphoMetriX #8)."""
    clicks = np.array([[0.0, 0.0], [150.0, 60.0], [300.0, 70.0], [460.0, 20.0]])
    forward, backward = place_stations(clicks), place_stations(clicks[::-1])
    assert backward.length_px == pytest.approx(forward.length_px, rel=1e-12)
    np.testing.assert_allclose(backward.points_px, forward.points_px[::-1], atol=1e-6)
    np.testing.assert_allclose(backward.normals, -forward.normals[::-1], atol=1e-9)
    half_a, half_b = np.linspace(5, 40, 19), np.linspace(8, 30, 19)
    edges = _edges(forward, half_a, half_b)
    widths = station_widths(forward, edges)
    reversed_edges = edges[::-1, ::-1]  # stations reversed, sides A and B swapped
    np.testing.assert_allclose(station_widths(backward, reversed_edges), widths[::-1], atol=1e-6)


def test_edge_points_are_projected_onto_the_perpendicular():
    """Edge clicks 3 px off the perpendicular still measure the width across the body."""
    stations = place_stations(np.array([[0.0, 0.0], [380.0, 0.0]]))
    half = np.linspace(10, 30, 19)
    exact = station_widths(stations, _edges(stations, half, half))
    shifted = station_widths(stations, _edges(stations, half, half, along_px=3.0))
    np.testing.assert_allclose(exact, 2 * half, atol=1e-12)
    np.testing.assert_allclose(shifted, exact, atol=1e-12)


def test_mirror_mode_doubles_one_side():
    """Mirror side A ignores side B: width = 2 × side A's distance from the midline."""
    stations = place_stations(np.array([[0.0, 0.0], [380.0, 0.0]]))
    half_a, half_b = np.full(19, 12.0), np.full(19, 20.0)
    edges = _edges(stations, half_a, half_b)
    edges[:, 1] = np.nan
    np.testing.assert_allclose(station_widths(stations, edges, "A"), 24.0, atol=1e-12)
    assert np.isnan(station_widths(stations, edges)).all()  # both sides needed otherwise


def test_pixel_measurements_of_an_annotation():
    """Length and widths in pixels, NaN at an unmarked station, mirror flag carried."""
    clicks = np.array([[10.0, 10.0], [410.0, 10.0]])
    stations = place_stations(clicks)
    edges = _edges(stations, np.full(19, 15.0), np.full(19, 15.0))
    edges[4] = np.nan
    pixels = pixel_measurements(Annotation(7, clicks, edges))
    assert pixels.length_px == pytest.approx(400.0)
    assert np.isnan(pixels.widths_px[4]) and not pixels.is_mirrored
    np.testing.assert_allclose(np.delete(pixels.widths_px, 4), 30.0, atol=1e-9)


@pytest.mark.parametrize("midline, edges, mirror, message", [
    ([[0.0, 0.0]], NO_EDGES, None, "N ≥ 2"),
    ([[0.0, 0.0], [0.0, 0.0]], NO_EDGES, None, "identical consecutive"),
    ([[0.0, 0.0], [5.0, 0.0]], np.zeros((18, 2, 2)), None, "edges_px must be"),
    ([[0.0, 0.0], [5.0, 0.0]], NO_EDGES, "C", "mirror_side"),
])
def test_annotation_rejects_bad_input(midline, edges, mirror, message):
    """Too few or repeated clicks, a wrong edge array or mirror side raise ValueError."""
    with pytest.raises(ValueError, match=message):
        Annotation(0, np.array(midline), edges, mirror)


def _ellipse_mask(centre, semi_major, semi_minor, angle, shape):
    """Binary mask of a rotated ellipse, pixel centres at integer coordinates."""
    v, u = np.mgrid[:shape[0], :shape[1]].astype(float)
    du, dv = u - centre[0], v - centre[1]
    along = du * math.cos(angle) + dv * math.sin(angle)
    across = -du * math.sin(angle) + dv * math.cos(angle)
    return (along / semi_major) ** 2 + (across / semi_minor) ** 2 <= 1.0


def test_mask_edges_of_an_ellipse_match_its_widths():
    """On a rotated 600 × 120 px ellipse the suggested widths are 2b·√(1 − (2p − 1)²)
    within 1 px (the mask's staircase boundary: up to half a pixel per side), unbiased."""
    centre, a, b, angle = np.array([400.0, 300.0]), 300.0, 60.0, math.radians(30)
    axis = np.array([math.cos(angle), math.sin(angle)])
    mask = _ellipse_mask(centre, a, b, angle, (600, 800))
    stations = place_stations(np.stack([centre - a * axis, centre + a * axis]))
    edges = suggest_edges(mask, stations)
    widths = station_widths(stations, edges)
    truth = 2 * b * np.sqrt(1 - (2 * STATION_FRACTIONS - 1) ** 2)
    np.testing.assert_allclose(widths, truth, atol=1.0)
    assert abs(np.mean(widths - truth)) < 0.2


def test_mask_edges_unseen_or_off_the_body_are_nan():
    """A station off the mask, or a body running out of the image, gives no edge."""
    mask = np.zeros((100, 400), dtype=bool)
    mask[40:60, 0:300] = True       # a bar that leaves the image at u = 0, ends at u = 299
    mask[:, 150:160] = True         # and a strip that reaches the top and bottom borders
    stations = place_stations(np.array([[0.0, 50.0], [380.0, 50.0]]))
    edges = suggest_edges(mask, stations)
    is_found = ~np.isnan(edges).any(axis=(1, 2))
    inside = (stations.points_px[:, 0] < 299) & ~((stations.points_px[:, 0] >= 149.5)
                                                   & (stations.points_px[:, 0] <= 160.5))
    assert is_found.tolist() == inside.tolist()
    np.testing.assert_allclose(station_widths(stations, edges)[is_found], 20.0, atol=1e-9)


def test_calibration_scales_by_altitude_over_focal_px():
    """Paper camera, 1920 px frames, 20 m: 20 / 1366.35 = 1.464 cm per pixel."""
    camera = CameraPreset("paper", "", 12.29, 17.27, 1920, 1080, "test", False)
    calibration = Calibration(camera, None, 20.0, "laser")
    assert calibration.focal_px == pytest.approx(1366.3463, abs=1e-4)
    assert calibration.m_per_px == pytest.approx(0.0146376, abs=1e-7)
    with pytest.raises(ValueError, match="altitude_source"):
        Calibration(camera, None, 20.0, "guess")


def test_polyline_stations_lie_on_the_segments_at_equal_arc_length():
    """Clicks (0, 0) → (300, 0) → (300, 100): length 400, station 50 % at (200, 0) with the
    first segment's normal, station 80 % at (300, 20) with the second's."""
    clicks = np.array([[0.0, 0.0], [300.0, 0.0], [300.0, 100.0]])
    stations = place_stations(clicks, midline="polyline")
    assert stations.length_px == pytest.approx(400.0, abs=1e-12)
    np.testing.assert_allclose(stations.points_px[9], [200.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(stations.points_px[15], [300.0, 20.0], atol=1e-12)
    np.testing.assert_allclose(stations.normals[9], [0.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(stations.normals[15], [-1.0, 0.0], atol=1e-12)


def test_chord_widths_are_the_distance_between_the_clicks():
    """A pair 30 px along the body and 40 px across: 50 px as a chord, 40 px projected; a
    mirrored side is twice its distance from the station point."""
    stations = place_stations(np.array([[0.0, 0.0], [400.0, 0.0]]))
    edges = np.full((19, 2, 2), np.nan)
    edges[4] = [[100.0, 20.0], [130.0, -20.0]]
    assert station_widths(stations, edges, widths="chord")[4] == pytest.approx(50.0)
    assert station_widths(stations, edges)[4] == pytest.approx(40.0)
    mirrored = station_widths(stations, edges, mirror_side="B", widths="chord")[4]
    assert mirrored == pytest.approx(2 * np.hypot(30.0, 20.0))


def test_unknown_geometry_is_refused():
    with pytest.raises(ValueError, match="midline must be one of"):
        Geometry(midline="bezier")
    with pytest.raises(ValueError, match="widths must be one of"):
        Geometry(widths="diagonal")
