"""Renderer behaviour: gradients, geometry, viewports, batching, shading, pyramid."""

import math

import numpy as np
import pytest
import torch
import torch.nn.functional as F

from dolphinfit.core.render.interpolate import barycentrics, interpolate_vertex_values
from dolphinfit.core.render.pyramid import (
    PYRAMID_LEVELS, gaussian_kernel, pyramid_loss, silhouette_pyramid,
)
from dolphinfit.core.render.rasterize import rasterize
from dolphinfit.core.render.render import project_to_viewport, render
from dolphinfit.core.render.settings import RasterSettings, Viewport
from dolphinfit.core.render.shade import (
    SGLight, sample_texture, sg_irradiance, vertex_normals, water_filter,
)
from dolphinfit.core.render.soft_mask import soft_mask

from .scenes import appearance, camera, ellipsoid, moved, two_ellipsoids


def test_gradcheck_soft_mask_and_colour_on_a_tiny_scene():
    """torch.autograd.gradcheck passes for vertices, texture and water in float64."""
    verts, faces, face_uvs = (torch.as_tensor(a) for a in ellipsoid((0.5, 0.25, 0.15),
                                                                   (0.0, 0.0, -0.2), 0))
    verts, face_uvs = verts.double(), face_uvs.double()
    app = appearance(face_uvs)
    cam = camera(24, 18, [1.2])
    viewport = Viewport.full_frame(cam.intrinsics, 1)
    pick = torch.Generator().manual_seed(0)
    probe = torch.rand(18, 24, generator=pick, dtype=torch.float64)

    def scalar(v, albedo, f_water):
        out = render(v[None], faces, type(app)(albedo, face_uvs, app.light, f_water), cam,
                     viewport)
        return (out.soft_mask * probe).sum() + (out.rgb.sum(-1) * probe).sum()

    inputs = (verts.clone().requires_grad_(), app.albedo.clone().requires_grad_(),
              app.f_water.clone().requires_grad_())
    assert torch.autograd.gradcheck(scalar, inputs, eps=1e-7, atol=1e-6, rtol=1e-4)


def test_projected_points_land_where_the_renderer_draws_them():
    """On a flat sheet at the surface, every covered pixel interpolates the world point that
    the camera unprojects from that pixel, and each interior vertex's nearest pixel is drawn
    by one of that vertex's own faces."""
    xs, ys = np.meshgrid(np.linspace(-1.0, 1.0, 9), np.linspace(-0.7, 0.7, 7))
    grid = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], 1)
    quads = [(r * 9 + c, r * 9 + c + 1, (r + 1) * 9 + c + 1, (r + 1) * 9 + c)
             for r in range(6) for c in range(8)]
    faces = torch.tensor([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    verts = torch.tensor(grid, dtype=torch.float64)[None] + torch.tensor([0.13, -0.07, 0.0],
                                                                        dtype=torch.float64)
    cam = camera(160, 120, [3.0], refraction=False)
    viewport = Viewport.full_frame(cam.intrinsics, 1)
    xy, depth = project_to_viewport(verts, cam, viewport)
    frags = rasterize(xy, depth, faces, 120, 160, 10**6)
    assert frags.pixel.numel() > 3000
    drawn = interpolate_vertex_values(verts, faces, frags, barycentrics(xy, faces, frags))
    expected = cam.unproject(frags.pixel_centres(torch.float64)[None])[0]
    # 1e-9 m: the barycentric denominator's signed 1e-8 px² epsilon over ~100 px² faces
    torch.testing.assert_close(drawn, expected, rtol=0, atol=1e-9)
    interior = [r * 9 + c for r in range(1, 6) for c in range(1, 8)]
    nearest_pixel = torch.round(xy[0, interior]).long()
    hit_faces = frags.face_idx[0, nearest_pixel[:, 1], nearest_pixel[:, 0]]
    assert all(v in faces[int(f)].tolist() for v, f in zip(interior, hit_faces))


def test_roi_render_equals_the_window_of_the_full_frame():
    """Rendering a crop gives the same pixels as cutting that window from the full frame."""
    verts, faces, face_uvs = two_ellipsoids()
    verts_t = moved(verts, [(0.1, 0.05, 0.0), (-0.2, 0.1, -0.4)], yaw_rad=-0.3)
    cam = camera(96, 72, [1.8, 1.5])
    app = appearance(face_uvs)
    full = render(verts_t, faces, app, cam, Viewport.full_frame(cam.intrinsics, 2))
    x0, y0 = torch.tensor([30, 22]), torch.tensor([20, 25])
    roi = render(verts_t, faces, app, cam, Viewport(x0, y0, 40, 30))
    for t in range(2):
        window = (slice(int(y0[t]), int(y0[t]) + 30), slice(int(x0[t]), int(x0[t]) + 40))
        torch.testing.assert_close(roi.face_idx[t], full.face_idx[t][window], rtol=0, atol=0)
        torch.testing.assert_close(roi.soft_mask[t], full.soft_mask[t][window], rtol=0,
                                   atol=1e-12)
        torch.testing.assert_close(roi.rgb[t], full.rgb[t][window], rtol=0, atol=1e-12)
    assert roi.coverage.sum() > 300


def test_batched_frames_equal_frames_rendered_one_by_one():
    """A batch of T frames renders exactly as T separate calls."""
    verts, faces, face_uvs = two_ellipsoids()
    verts_t = moved(verts, [(0.0, 0.0, 0.0), (0.2, -0.1, -0.3), (-0.1, 0.3, 0.05)], 0.7)
    cam = camera(48, 36, [1.5, 1.7, 1.4])
    app = appearance(face_uvs)
    batch = render(verts_t, faces, app, cam, Viewport.full_frame(cam.intrinsics, 3))
    for t in range(3):
        single = render(verts_t[t:t + 1], faces, app, cam.select([t]),
                        Viewport.full_frame(cam.intrinsics, 1))
        torch.testing.assert_close(batch.soft_mask[t], single.soft_mask[0], rtol=0, atol=1e-12)
        torch.testing.assert_close(batch.rgb[t], single.rgb[0], rtol=0, atol=1e-12)


def test_sg_irradiance_matches_quadrature_over_the_sphere():
    """E(n) agrees with ∫ max(ω·n, 0) G(ω) dω within 5 % for normals within 40° of a λ = 5 lobe.

    5 % is the accuracy of fitting the clamped cosine with one SG lobe there (measured 2–4 %);
    it degrades for sharper lobes and grazing normals, which a wrong formula would not explain.
    """
    light = SGLight(axes=torch.tensor([[0.0, 0.6, 0.8]], dtype=torch.float64),
                    sharpness=torch.tensor([5.0], dtype=torch.float64),
                    amplitude=torch.tensor([[1.0, 2.0, 0.5]], dtype=torch.float64))
    normals = torch.tensor([[0.0, 0.0, 1.0], [0.0, 0.6, 0.8], [0.6, 0.0, 0.8]],
                           dtype=torch.float64)
    theta, phi = torch.meshgrid(torch.linspace(0, math.pi, 801, dtype=torch.float64),
                                torch.linspace(0, 2 * math.pi, 1601, dtype=torch.float64),
                                indexing="ij")
    omega = torch.stack([torch.sin(theta) * torch.cos(phi), torch.sin(theta) * torch.sin(phi),
                         torch.cos(theta)], -1)
    area = torch.sin(theta) * (math.pi / 800) * (2 * math.pi / 1600)
    lobe = torch.exp(light.sharpness[0] * (omega @ light.axes[0] - 1.0))
    for n, estimate in zip(normals, sg_irradiance(normals, light)):
        exact = ((omega @ n).clamp(min=0) * lobe * area).sum() * light.amplitude[0]
        torch.testing.assert_close(estimate, exact, rtol=0.05, atol=0)


def test_texture_sampling_is_bilinear_with_texel_centres():
    """At texel centres the texel value comes back; halfway between two, their mean."""
    texture = torch.tensor([[0.0, 1.0], [2.0, 3.0]], dtype=torch.float64)[..., None]
    uv = torch.tensor([[0.25, 0.25], [0.75, 0.75], [0.5, 0.25], [0.5, 0.5], [0.0, 0.0]],
                      dtype=torch.float64)
    torch.testing.assert_close(sample_texture(texture, uv)[:, 0],
                               torch.tensor([0.0, 3.0, 0.5, 1.5, 0.0], dtype=torch.float64))


def test_water_filter_attenuates_with_depth_only_below_the_surface():
    """Ĉ = C·exp(min(z, 0)·F): unchanged above water, e^{−F·d} below."""
    colour = torch.ones(3, 3, dtype=torch.float64)
    height = torch.tensor([0.5, 0.0, -2.0], dtype=torch.float64)
    f_water = torch.tensor([0.5, 0.2, 0.0], dtype=torch.float64)
    out = water_filter(colour, height, f_water)
    torch.testing.assert_close(out[0], colour[0])
    torch.testing.assert_close(out[2], torch.exp(torch.tensor([-1.0, -0.4, 0.0],
                                                              dtype=torch.float64)))


@pytest.mark.parametrize("height, width", [(72, 96), (37, 29), (5, 3)])
def test_pyramid_levels_are_average_pooling_then_a_zero_padded_gaussian_blur(height, width):
    """Each level equals torch's average pooling (ceil mode: a partial last window averages
    the pixels it holds) followed by the separable Gaussian as two convolutions."""
    masks = torch.rand(2, height, width, dtype=torch.float64)
    for (factor, sigma), level in zip(PYRAMID_LEVELS, silhouette_pyramid(masks)):
        pooled = F.avg_pool2d(masks[:, None], factor, ceil_mode=True)
        kernel = gaussian_kernel(sigma, torch.float64)
        radius = (len(kernel) - 1) // 2
        blurred = F.conv2d(pooled, kernel.reshape(1, 1, 1, -1), padding=(0, radius))
        blurred = F.conv2d(blurred, kernel.reshape(1, 1, -1, 1), padding=(radius, 0))
        torch.testing.assert_close(level, blurred[:, 0], rtol=1e-12, atol=1e-12)


def test_pyramid_loss_pulls_a_non_overlapping_silhouette():
    """With no overlap IoU has no gradient, but the pyramid term points towards the target."""
    verts, faces, _ = (torch.as_tensor(a) for a in ellipsoid((0.4, 0.15, 0.1), (0, 0, 0)))
    verts = verts.double()
    cam = camera(96, 72, [3.0], refraction=False)
    viewport = Viewport.full_frame(cam.intrinsics, 1)
    shift = torch.tensor([0.0, 0.0, 0.0], dtype=torch.float64, requires_grad=True)
    def silhouette(offset):
        xy, depth = project_to_viewport((verts + offset)[None], cam, viewport)
        frags = rasterize(xy, depth, faces, 72, 96, 10**6)
        return soft_mask(xy, depth, faces, frags, RasterSettings())

    target = silhouette(torch.tensor([1.5, 0.0, 0.0], dtype=torch.float64)).detach()
    rendered = silhouette(shift)
    assert float((rendered.detach() * target).sum()) == 0.0
    (grad,) = torch.autograd.grad(pyramid_loss(rendered, silhouette_pyramid(target)), shift)
    assert float(grad[0]) < 0  # moving towards +x lowers the loss


def test_vertex_normals_are_the_normalised_sum_of_the_adjacent_faces_area_normals():
    """Against the formula written plainly (cross product per face, summed per vertex), and
    outward: on an ellipsoid they point away from its centre."""
    verts, faces, _ = (torch.as_tensor(a) for a in ellipsoid((0.5, 0.25, 0.15), (0, 0, 0)))
    verts = moved(verts.double(), [(0.0, 0.0, 0.0), (0.1, -0.2, 0.3)], yaw_rad=0.4)
    normals = vertex_normals(verts, faces)
    corners = verts[:, faces]                                        # (T, F, 3, 3)
    face_normals = torch.linalg.cross(corners[:, :, 1] - corners[:, :, 0],
                                      corners[:, :, 2] - corners[:, :, 0], dim=-1)
    expected = torch.zeros_like(verts)
    for t in range(verts.shape[0]):
        for k in range(3):
            expected[t].index_add_(0, faces[:, k], face_normals[t])
    expected = expected / expected.norm(dim=-1, keepdim=True)
    torch.testing.assert_close(normals, expected, rtol=0, atol=1e-12)
    outward = ((verts - verts.mean(1, keepdim=True)) * normals).sum(-1)
    assert bool((outward > 0).all())


@pytest.mark.parametrize("primitives", ["contour", "faces"])
def test_a_viewport_the_animal_covers_whole_renders_with_no_soft_edge(primitives):
    """No uncovered pixel, so no (pixel, primitive) pair: the soft mask is the coverage."""
    verts, faces, face_uvs = (torch.as_tensor(a) for a in ellipsoid((0.5, 0.25, 0.15),
                                                                   (0.0, 0.0, 0.0), 0))
    cam = camera(96, 72, [1.8])
    out = render(verts.double()[None], faces, appearance(face_uvs.double()), cam,
                 Viewport(torch.tensor([44]), torch.tensor([32]), 8, 8),
                 RasterSettings(soft_primitives=primitives))
    assert bool(out.coverage.all())
    torch.testing.assert_close(out.soft_mask, torch.ones(1, 8, 8, dtype=torch.float64))


@pytest.mark.parametrize("primitives", ["contour", "faces"])
def test_a_viewport_the_animal_never_enters_renders_water_only(primitives):
    """No covered pixel (an animal out of view; a synthetic clip once crashed on it): the
    soft mask and coverage are empty, and the colour and gradients are still defined."""
    verts, faces, face_uvs = (torch.as_tensor(a) for a in ellipsoid((0.5, 0.25, 0.15),
                                                                   (0.0, 0.0, 0.0), 0))
    cam = camera(96, 72, [1.8])
    verts_t = verts.double()[None].clone().requires_grad_(True)
    out = render(verts_t, faces, appearance(face_uvs.double()), cam,
                 Viewport(torch.tensor([0]), torch.tensor([0]), 8, 8),
                 RasterSettings(soft_primitives=primitives))
    assert not bool(out.coverage.any())
    assert float(out.soft_mask.max()) < 1e-6
    assert bool(torch.isfinite(out.rgb).all())
    (out.soft_mask.sum() + out.rgb.sum()).backward()
    assert bool(torch.isfinite(verts_t.grad).all())
