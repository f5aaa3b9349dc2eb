"""The sparse renderer against the dense brute-force reference: results and gradients."""

import pytest
import torch

from dolphinfit.core.render.dense import dense_render
from dolphinfit.core.render.render import project_to_viewport, render
from dolphinfit.core.render.settings import RasterSettings, Viewport

from .scenes import appearance, camera, moved, two_ellipsoids

WIDTH, HEIGHT = 64, 48
SETTINGS = {
    "paper": RasterSettings(soft_primitives="faces"),
    "k binds": RasterSettings(sigma_inv=7000.0, box_len=0.05, max_faces_per_pixel=3,
                              soft_primitives="faces"),
    "tiny chunks": RasterSettings(max_pairs_per_chunk=97, soft_primitives="faces"),
    "contour": RasterSettings(),
    "contour, k binds": RasterSettings(sigma_inv=7000.0, box_len=0.05, max_faces_per_pixel=2),
    "contour, tiny chunks": RasterSettings(max_pairs_per_chunk=97),
}


def _scene():
    verts, faces, face_uvs = two_ellipsoids()
    verts_t = moved(verts, [(0.05, -0.1, 0.0), (-0.3, 0.2, -0.2)], yaw_rad=0.4)
    cam = camera(WIDTH, HEIGHT, [1.6, 1.3])
    return verts_t, faces, appearance(face_uvs), cam, Viewport.full_frame(cam.intrinsics, 2)


@pytest.mark.parametrize("name", list(SETTINGS))
def test_results_match_dense_reference(name):
    """Identical face-index maps, soft masks within 1e-6, colours within 1e-12."""
    settings = SETTINGS[name]
    verts, faces, app, cam, viewport = _scene()
    out = render(verts, faces, app, cam, viewport, settings)
    xy, depth = project_to_viewport(verts, cam, viewport)
    face_idx, soft, rgb = dense_render(verts, xy, depth, faces, app, HEIGHT, WIDTH, settings)
    assert out.coverage.sum() > 200
    assert ((out.soft_mask > 0.01) & ~out.coverage).sum() > 50
    torch.testing.assert_close(out.face_idx, face_idx, rtol=0, atol=0)
    torch.testing.assert_close(out.soft_mask, soft, rtol=0, atol=1e-6)
    torch.testing.assert_close(out.rgb, rgb, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", ["paper", "k binds", "contour", "contour, k binds"])
def test_gradients_match_dense_reference(name):
    """Gradients of a scalar loss w.r.t. vertices, texture, water and light agree to 1e-4."""
    settings = SETTINGS[name]
    verts, faces, app, cam, viewport = _scene()
    weights = torch.linspace(0.5, 1.5, 3, dtype=torch.float64)
    target = torch.rand(2, HEIGHT, WIDTH, generator=torch.Generator().manual_seed(1),
                        dtype=torch.float64)

    def gradients(renderer):
        leaves = [verts.clone().requires_grad_(), app.albedo.clone().requires_grad_(),
                  app.f_water.clone().requires_grad_(), app.light.axes.clone().requires_grad_(),
                  app.light.sharpness.clone().requires_grad_(),
                  app.light.amplitude.clone().requires_grad_()]
        soft, rgb = renderer(*leaves)
        loss = ((soft - target) ** 2).sum() + (rgb * weights).sum()
        return torch.autograd.grad(loss, leaves)

    def sparse(v, albedo, f_water, axes, sharpness, amplitude):
        light = type(app.light)(axes, sharpness, amplitude)
        out = render(v, faces, type(app)(albedo, app.face_uvs, light, f_water), cam, viewport,
                     settings)
        return out.soft_mask, out.rgb

    def dense(v, albedo, f_water, axes, sharpness, amplitude):
        light = type(app.light)(axes, sharpness, amplitude)
        xy, depth = project_to_viewport(v, cam, viewport)
        _, soft, rgb = dense_render(v, xy, depth, faces,
                                    type(app)(albedo, app.face_uvs, light, f_water),
                                    HEIGHT, WIDTH, settings)
        return soft, rgb

    for got, expected in zip(gradients(sparse), gradients(dense)):
        assert expected.abs().max() > 0
        scale = expected.abs().max()
        assert ((got - expected).abs().max() / scale) < 1e-4
