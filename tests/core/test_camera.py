"""Tests for core/camera.py: intrinsics, projection round trips, crops, refraction."""

import math

import numpy as np
import pytest
import torch
from scipy.optimize import minimize, root

from dolphinfit.core.camera import N_WATER, NadirCamera, apparent_surface_point
from dolphinfit.core.intrinsics import CameraIntrinsics

PAPER_SENSOR_WIDTH_MM = 17.27  # γ, Baieri et al. arXiv 2504.15782, table of constants
PAPER_FOCAL_MM = 12.29  # ω, same table
F64 = torch.float64


@pytest.fixture
def fhd() -> CameraIntrinsics:
    """The paper's camera on a 1920×1080 frame."""
    return CameraIntrinsics.from_sensor(PAPER_FOCAL_MM, PAPER_SENSOR_WIDTH_MM, 1920, 1080)


def _camera(intrinsics, altitudes, refraction=True) -> NadirCamera:
    return NadirCamera(intrinsics, torch.tensor(altitudes, dtype=F64), refraction=refraction)


# --- intrinsics ------------------------------------------------------------------------------


def test_paper_camera_field_of_view_is_70_2_degrees(fhd):
    """2·atan(γ/2ω) with γ = 17.27 mm, ω = 12.29 mm is 70.2° (the paper's value)."""
    assert math.degrees(fhd.fov_x_rad) == pytest.approx(70.2, abs=0.05)
    assert fhd.fov_x_rad == pytest.approx(2 * math.atan(17.27 / (2 * 12.29)), rel=1e-12)


def test_paper_camera_focal_px_and_principal_point(fhd):
    """f = 12.29 / 17.27 × 1920 = 1366.35 px; principal point at the image centre."""
    assert fhd.focal_px == pytest.approx(1366.3463, abs=1e-4)
    assert (fhd.cx_px, fhd.cy_px) == (959.5, 539.5)


def test_paper_camera_gsd_at_20_m_is_1_46_cm(fhd):
    """At 20 m on 1920 px the ground sampling distance is 20 / 1366.35 = 1.464 cm/px."""
    assert fhd.gsd_m_per_px(20.0) == pytest.approx(0.0146376, abs=1e-7)


def test_from_sensor_rejects_non_positive_values():
    """A zero or negative focal length raises ValueError quoting the value."""
    with pytest.raises(ValueError, match="-12.29"):
        CameraIntrinsics.from_sensor(-12.29, 17.27, 1920, 1080)
    with pytest.raises(ValueError, match="image_width_px"):
        CameraIntrinsics.from_sensor(12.29, 17.27, 0, 1080)


def test_crop_shifts_principal_point_and_may_exceed_image(fhd):
    """A crop keeps f, subtracts (x0, y0) from the principal point, and may leave the image."""
    roi = fhd.crop(1800, -20, 300, 200)
    assert (roi.focal_px, roi.cx_px, roi.cy_px) == (fhd.focal_px, -840.5, 559.5)
    assert (roi.width_px, roi.height_px) == (300, 200)


def test_resized_rejects_a_changed_aspect(fhd):
    """Resizing 1920×1080 to 720×480 changes the aspect ratio and raises ValueError."""
    with pytest.raises(ValueError, match="aspect"):
        fhd.resized(720, 480)


# --- projection ------------------------------------------------------------------------------


@pytest.mark.parametrize("refraction", [False, True])
@pytest.mark.parametrize("depth_m", [0.0, 0.3, 1.5, 3.0])
def test_project_unproject_round_trip(fhd, refraction, depth_m):
    """Points at one depth, 3 frames at 12/20/35 m, come back from their pixels to 1e-9 m."""
    camera = _camera(fhd, [12.0, 20.0, 35.0], refraction)
    gen = torch.Generator().manual_seed(0)
    points = torch.rand(3, 50, 3, generator=gen, dtype=F64) * 16 - 8
    points[..., 2] = -depth_m
    xy_px = camera.project(points)
    back = camera.unproject(xy_px, plane_z_m=-depth_m)
    assert back.shape == (3, 50, 3)
    assert (back - points).abs().max().item() < 1e-9


def test_unproject_with_per_frame_planes(fhd):
    """plane_z_m as a (T,) tensor puts each frame's points on its own plane (refracted)."""
    camera = _camera(fhd, [15.0, 25.0])
    depths = torch.tensor([-0.4, -2.2], dtype=F64)
    points = torch.tensor([[[3.0, -1.0, 0.0], [-6.0, 2.5, 0.0]]], dtype=F64).repeat(2, 1, 1)
    points[..., 2] = depths[:, None]
    back = camera.unproject(camera.project(points), plane_z_m=depths)
    assert (back - points).abs().max().item() < 1e-9


def test_unproject_on_water_plane_scales_by_gsd(fhd):
    """A pixel 100 px right of the principal point at 20 m lies 100·GSD m along +x."""
    camera = _camera(fhd, [20.0])
    world = camera.unproject(torch.tensor([[fhd.cx_px + 100, fhd.cy_px]], dtype=F64))
    np.testing.assert_allclose(world.numpy(), [[[100 * 20 / fhd.focal_px, 0.0, 0.0]]], atol=1e-12)


def test_image_axes_follow_world_axes(fhd):
    """World +x goes to image +u and world +y to image −v (up)."""
    camera = _camera(fhd, [20.0], refraction=False)
    xy = camera.project(torch.tensor([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], dtype=F64))[0]
    step_px = fhd.focal_px / 20
    np.testing.assert_allclose(
        xy.numpy(), [[959.5 + step_px, 539.5], [959.5, 539.5 - step_px]], atol=1e-9
    )


def test_crop_camera_projects_to_shifted_pixels(fhd):
    """A vertex seen through an ROI lands at the full-frame pixel minus (x0, y0)."""
    camera = _camera(fhd, [18.0, 22.0])
    roi = camera.crop(700, 350, 480, 320)
    points = torch.tensor([[[1.2, 0.7, -0.8], [-0.5, 2.0, 0.1], [0.0, 0.0, -1.0]]], dtype=F64)
    shifted = camera.project(points) - torch.tensor([700.0, 350.0], dtype=F64)
    assert (roi.project(points) - shifted).abs().max().item() < 1e-9


@pytest.mark.parametrize("size", [(960, 540), (720, 405), (3840, 2160)])
def test_resized_intrinsics_scale_about_pixel_centres(fhd, size):
    """Projecting with resized intrinsics gives (u + 0.5)·s − 0.5 of the full-size pixel."""
    scale = size[0] / fhd.width_px
    full = _camera(fhd, [20.0])
    small = _camera(fhd.resized(*size), [20.0])
    points = torch.tensor([[3.0, -2.0, -1.2], [-7.5, 4.0, 0.0], [0.0, 0.0, -0.5]], dtype=F64)
    expected = (full.project(points) + 0.5) * scale - 0.5
    assert (small.project(points) - expected).abs().max().item() < 1e-9


@pytest.mark.parametrize("factor", [2, 4])
def test_binned_intrinsics_map_pixel_centres_exactly_at_any_size(factor):
    """A 2978 × 1985 still (odd rows): a point seen at pixel u in the full image is seen at
    (u + 0.5) / factor − 0.5 with the binned intrinsics; on 1920 × 1080 they equal the
    resized ones."""
    still = CameraIntrinsics.from_sensor(8.8, 13.2, 2978, 1985)
    full = _camera(still, [30.0])
    binned = _camera(still.binned(factor), [30.0])
    points = torch.tensor([[3.0, -2.0, -1.2], [-7.5, 4.0, 0.0], [0.0, 0.0, -0.5]], dtype=F64)
    expected = (full.project(points) + 0.5) / factor - 0.5
    assert (binned.project(points) - expected).abs().max().item() < 1e-9
    assert (still.binned(factor).width_px, still.binned(factor).height_px) == (
        2978 // factor, 1985 // factor)
    fhd = CameraIntrinsics.from_sensor(12.29, 17.27, 1920, 1080)
    assert fhd.binned(factor) == fhd.resized(1920 // factor, 1080 // factor)


def test_project_dtype_follows_input(fhd):
    """float32 points give float32 pixels within 2e-3 px of the float64 result."""
    camera = NadirCamera(fhd, torch.tensor([20.0]))
    points = torch.tensor([[4.0, -3.0, -1.0], [0.2, 0.1, 0.3]])
    xy32 = camera.project(points)
    xy64 = camera.project(points.to(F64))
    assert xy32.dtype == torch.float32
    assert (xy32.to(F64) - xy64).abs().max().item() < 2e-3


def test_points_batch_of_one_broadcasts_over_frames(fhd):
    """(1, N, 3) points with T = 4 altitudes give (4, N, 2) pixels."""
    camera = _camera(fhd, [10.0, 15.0, 20.0, 25.0])
    points = torch.tensor([[[1.0, 2.0, -0.5], [0.0, -1.0, 0.2]]], dtype=F64)
    xy = camera.project(points)
    assert xy.shape == (4, 2, 2)
    assert xy[3, 0, 0].item() == pytest.approx(959.5 + fhd.focal_px * 1.0 / 25.0, rel=1e-2)


def test_mismatched_batch_raises_naming_both_counts(fhd):
    """T = 3 points with T = 4 altitudes raises ValueError mentioning 3 and 4."""
    camera = _camera(fhd, [10.0, 15.0, 20.0, 25.0])
    with pytest.raises(ValueError, match=r"3 frames.*4 altitudes"):
        camera.project(torch.zeros(3, 5, 3, dtype=F64))


def test_point_at_camera_height_raises(fhd):
    """A point at the camera's altitude cannot be projected."""
    camera = _camera(fhd, [20.0])
    with pytest.raises(ValueError, match="above the camera"):
        camera.project(torch.tensor([[1.0, 1.0, 20.0]], dtype=F64))


def test_select_and_gsd_per_frame(fhd):
    """select() keeps the chosen frames' altitudes; gsd_m_per_px is altitude / f per frame."""
    camera = _camera(fhd, [10.0, 20.0, 30.0]).select([2, 0])
    assert camera.num_frames == 2
    np.testing.assert_allclose(
        camera.gsd_m_per_px().numpy(), [30 / fhd.focal_px, 10 / fhd.focal_px], rtol=1e-15
    )
    assert camera.select(1).altitude_m.tolist() == [10.0]


# --- refraction ------------------------------------------------------------------------------


def test_point_straight_below_projects_to_principal_point(fhd):
    """A point straight below the camera lands on the same pixel with and without refraction."""
    point = torch.tensor([[0.0, 0.0, -2.0]], dtype=F64)
    refracted = _camera(fhd, [20.0], refraction=True).project(point)
    straight = _camera(fhd, [20.0], refraction=False).project(point)
    np.testing.assert_allclose(refracted.numpy(), [[[959.5, 539.5]]], atol=1e-12)
    np.testing.assert_allclose(straight.numpy(), refracted.numpy(), atol=1e-12)


def test_submerged_point_appears_between_straight_and_surface(fhd):
    """Off axis, refraction pushes the image outwards, but less than raising the point to z = 0."""
    refracted = _camera(fhd, [20.0], refraction=True)
    straight = _camera(fhd, [20.0], refraction=False)
    points = torch.tensor([[4.0, 3.0, -2.0], [4.0, 3.0, 0.0]], dtype=F64)
    radius = lambda xy: torch.linalg.norm(xy - torch.tensor([959.5, 539.5], dtype=F64), dim=-1)
    r_refracted = radius(refracted.project(points[:1]))[0, 0].item()
    r_straight = radius(straight.project(points[:1]))[0, 0].item()
    r_surface = radius(straight.project(points[1:]))[0, 0].item()
    # 5 m off axis at 20 m: straight 5·f/22 = 310.5 px, raised 5·f/20 = 341.6 px, and about
    # 5·f/(20 + 2/n) = 317.8 px seen at the apparent depth d/n
    assert r_straight == pytest.approx(310.53, abs=0.01)
    assert r_surface == pytest.approx(341.59, abs=0.01)
    assert r_refracted == pytest.approx(317.8, abs=0.5)
    assert r_straight < r_refracted < r_surface


def _fermat_surface_point(altitude_m: float, q: np.ndarray, n: float) -> np.ndarray:
    """S on z = 0 minimising the optical path |C − S| + n·|S − Q| (Fermat's principle).

    BFGS on the path length with its analytic gradient, then the stationary point polished by
    a root finder on that gradient (a minimiser alone locates S only to about √ε).
    """
    camera = np.array([0.0, 0.0, altitude_m])

    def optical_path(s_xy: np.ndarray) -> tuple[float, np.ndarray]:
        s = np.array([s_xy[0], s_xy[1], 0.0])
        to_camera, to_point = np.linalg.norm(s - camera), np.linalg.norm(s - q)
        gradient = (s - camera)[:2] / to_camera + n * (s - q)[:2] / to_point
        return to_camera + n * to_point, gradient

    coarse = minimize(optical_path, q[:2] * 0.9, jac=True, method="BFGS",
                      options={"gtol": 1e-12})
    return root(lambda s_xy: optical_path(s_xy)[1], coarse.x, tol=1e-15).x


def test_apparent_surface_point_matches_fermat_minimiser(fhd):
    """Snell's-law solve agrees with Fermat's principle to 1e-9 over depths, offsets, altitudes."""
    direction = np.array([0.6, -0.8])
    cases = [(h, d, rho) for h in (10.0, 25.0, 40.0) for d in (0.1, 1.0, 3.0)
             for rho in (0.0, 0.5, 5.0, 15.0)]
    q = np.array([[*(rho * direction), -d] for _, d, rho in cases])
    altitudes = np.array([h for h, _, _ in cases])
    ours = apparent_surface_point(torch.tensor(q), torch.tensor(altitudes)).numpy()
    fermat = np.array([_fermat_surface_point(h, qi, N_WATER) for h, qi in zip(altitudes, q)])
    rho = np.array([c[2] for c in cases])
    r_ours, r_fermat = np.linalg.norm(ours[:, :2], axis=1), np.linalg.norm(fermat, axis=1)
    assert np.all(ours[:, 2] == 0)
    np.testing.assert_allclose(r_ours, r_fermat, rtol=1e-9, atol=1e-12)
    assert np.all(r_ours <= rho) and np.all(r_ours[rho > 0] > 0)
    # the same agreement in pixels, one camera per case
    for (h, _, _), qi, s in zip(cases, q, fermat):
        xy = _camera(fhd, [h]).project(torch.tensor(qi[None]))[0, 0].numpy()
        expected = [fhd.cx_px + fhd.focal_px * s[0] / h, fhd.cy_px - fhd.focal_px * s[1] / h]
        np.testing.assert_allclose(xy, expected, rtol=0, atol=1e-6)


def test_apparent_depth_near_nadir(fhd):
    """Near the nadir a submerged segment looks (h + d)/(h + d/n) times longer than straight."""
    h, d = 20.0, 1.5
    segment = torch.tensor([[0.3, 0.2, -d], [0.4, 0.2, -d]], dtype=F64)
    length = lambda xy: torch.linalg.norm(xy[0, 1] - xy[0, 0]).item()
    refracted = length(_camera(fhd, [h], refraction=True).project(segment))
    straight = length(_camera(fhd, [h], refraction=False).project(segment))
    assert refracted / straight == pytest.approx((h + d) / (h + d / N_WATER), rel=1e-3)
    # DESIGN.md §3: 1 m down at 20 m, lengths look about 1.2 % longer
    assert (21.0 / (20.0 + 1.0 / N_WATER)) == pytest.approx(1.012, abs=5e-4)


def test_apparent_surface_point_leaves_points_above_water(fhd):
    """Points with z ≥ 0 come back unchanged, with identity gradient and no NaN."""
    points = torch.tensor([[1.0, -2.0, 0.0], [3.0, 1.0, 0.7]], dtype=F64, requires_grad=True)
    out = apparent_surface_point(points, 20.0)
    out.sum().backward()
    assert torch.equal(out, points.detach())
    assert points.grad.tolist() == [[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]


def test_nadir_gradient_is_paraxial_fraction():
    """Straight below the camera dS_x/dx is the paraxial fraction n·h/(d + n·h), not NaN."""
    h, d = 20.0, 2.0
    point = torch.tensor([0.0, 0.0, -d], dtype=F64, requires_grad=True)
    apparent_surface_point(point, h)[0].backward()
    expected = N_WATER * h / (d + N_WATER * h)
    np.testing.assert_allclose(point.grad.numpy(), [expected, 0.0, 0.0], atol=1e-12)


def test_apparent_surface_point_float32_in_float32_out():
    """float32 input is solved in float64 and returned as float32."""
    out = apparent_surface_point(torch.tensor([[5.0, 0.0, -1.0]]), torch.tensor(20.0))
    assert out.dtype == torch.float32
    assert 0.0 < out[0, 0].item() < 5.0


def test_gradcheck_apparent_surface_point():
    """Autograd gradients of the apparent point match finite differences (float64)."""
    points = torch.tensor([[2.0, -1.0, -0.7], [0.0, 0.0, -1.3], [6.0, 4.0, -0.05],
                           [-3.0, 2.0, -2.5], [1.0, 1.0, 0.4]], dtype=F64, requires_grad=True)
    altitude = torch.tensor([12.0, 15.0, 20.0, 30.0, 18.0], dtype=F64, requires_grad=True)
    assert torch.autograd.gradcheck(apparent_surface_point, (points, altitude), atol=1e-7)


def test_gradcheck_project_with_refraction():
    """project() gradients to points and altitudes match finite differences (float64)."""
    intrinsics = CameraIntrinsics(focal_px=100.0, cx_px=31.5, cy_px=23.5, width_px=64,
                                  height_px=48)
    # above water, below, straight below the camera, just under the surface; two frames
    points = torch.tensor(
        [[[1.0, -0.5, 0.4], [2.0, 1.5, -1.2], [0.0, 0.0, -0.8], [-3.0, 0.2, -0.05]],
         [[0.5, 0.5, 0.1], [-2.0, 1.0, -2.0], [0.0, 0.0, -0.3], [4.0, -4.0, -0.6]]],
        dtype=F64, requires_grad=True,
    )
    altitude = torch.tensor([8.0, 15.0], dtype=F64, requires_grad=True)
    project = lambda p, h: NadirCamera(intrinsics, h, refraction=True).project(p)
    assert torch.autograd.gradcheck(project, (points, altitude), atol=1e-6)
