"""The fitted silhouette on the frame: the straight nadir projection and its outline."""

import numpy as np
import pytest
import trimesh

from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.project.fit_overlay import project_straight, silhouette_outlines

INTRINSICS = CameraIntrinsics.from_sensor(12.29, 17.27, 1920, 1080)


def test_projection_matches_the_gsd_and_the_principal_point():
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, -1.0]])
    uv = project_straight(points, INTRINSICS, 20.0)
    np.testing.assert_allclose(uv[0], [INTRINSICS.cx_px, INTRINSICS.cy_px])
    assert uv[1, 0] - uv[0, 0] == pytest.approx(1.0 / INTRINSICS.gsd_m_per_px(20.0))
    assert uv[2, 1] < uv[0, 1]  # world +y is image up; deeper points look nearer the centre
    assert INTRINSICS.cy_px - uv[2, 1] == pytest.approx(INTRINSICS.focal_px / 21.0)


def test_a_sphere_outlines_as_its_projected_circle():
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    verts = np.asarray(sphere.vertices) + [2.0, -1.0, -1.5]
    outlines = silhouette_outlines(verts, np.asarray(sphere.faces), INTRINSICS, 20.0)
    assert len(outlines) == 1
    centre = project_straight(np.array([[2.0, -1.0, -1.5]]), INTRINSICS, 20.0)[0]
    radii = np.linalg.norm(outlines[0] - centre, axis=1)
    # a sphere of radius 1 m at depth 21.5 m below the camera: radius f·r / √(d² − r²); the
    # outline runs through the centres of the edge pixels (≤ 1 px inside the true edge) and
    # the icosphere's facets and the slight off-axis ellipse add a few tenths of a pixel
    expected = INTRINSICS.focal_px * 1.0 / np.sqrt(21.5 ** 2 - 1.0)
    np.testing.assert_allclose(radii, expected, atol=1.5)
    assert abs(np.median(radii) - expected) < 1.0
    with pytest.raises(ValueError):
        silhouette_outlines(verts + [0, 0, 30.0], np.asarray(sphere.faces), INTRINSICS, 20.0)
