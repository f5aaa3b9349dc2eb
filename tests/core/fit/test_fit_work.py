"""What each step of a fit renders: frame subsets and the coarse copy of the data."""

from dataclasses import replace

import numpy as np
import pytest
import torch

from dolphinfit.core.fit import objective, scene, schedule
from dolphinfit.core.fit.config import FitConfig, LossWeights
from dolphinfit.core.fit.data import downscaled
from dolphinfit.core.fit.engine import fit
from dolphinfit.core.fit.objective import equal_chunks, evenly_spaced
from dolphinfit.core.fit.init import initial_state, silhouette_centroid_offset
from dolphinfit.core.fit.reporter import FitReporter
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.template import load_template
from dolphinfit.core.render.render import project_to_viewport
from dolphinfit.core.render.settings import Viewport

from .test_fit import TINY, _data


def test_evenly_spaced_keeps_the_ends_and_at_most_the_limit():
    frames = torch.arange(10, 20)
    assert evenly_spaced(frames, 4).tolist() == [10, 13, 16, 19]
    assert evenly_spaced(frames, 0).tolist() == list(range(10, 20))
    assert evenly_spaced(frames, 12).tolist() == list(range(10, 20))


def test_coarse_data_is_the_same_scene_at_half_resolution(clip_dir):
    """Half-resolution windows: each pixel the mean of its 2×2 block, and every world point
    projects to (native + 0.5) / 2 − 0.5, the same physical spot."""
    data = _data(clip_dir)
    coarse = downscaled(data, 2)
    assert coarse is not None
    assert coarse.images.shape[1:3] == (data.images.shape[1] // 2, data.images.shape[2] // 2)
    torch.testing.assert_close(coarse.images[0, 3, 5], data.images[0, 6:8, 10:12].mean((0, 1)))
    points = torch.tensor([[[0.3, -0.2, 0.0], [-1.0, 0.5, -0.4], [0.0, 0.0, 0.1]]]).expand(
        data.num_frames, -1, -1)
    native, _ = project_to_viewport(points, data.camera, data.viewport)
    half, _ = project_to_viewport(points, coarse.camera, coarse.viewport)
    torch.testing.assert_close(half, (native + 0.5) / 2 - 0.5, rtol=0, atol=1e-3)


def test_windows_off_the_coarse_grid_have_no_coarse_copy(clip_dir):
    data = _data(clip_dir)
    shifted = replace(data, viewport=Viewport(data.viewport.x0_px + 1, data.viewport.y0_px,
                                              data.viewport.width_px, data.viewport.height_px))
    assert downscaled(shifted, 2) is None
    assert downscaled(data, 3) is None or data.viewport.width_px % 3 == 0


@pytest.mark.parametrize("coarse_factor", [1, 2])
def test_heading_and_shape_render_subsets_and_the_shape_ends_on_all(
        clip_dir, monkeypatch, coarse_factor):
    """Heading trials render heading_max_frames frames at the coarse resolution; the first
    coarse_steps pose steps (global, then body) render at 1/coarse_factor of the native
    window, the rest natively; the shape stage renders shape_max_frames of its frames until
    its last shape_full_steps steps, which render all of them."""
    config = replace(TINY, heading_trial_steps=2, steps_global=2, steps_body=2, steps_shape=5,
                     heading_max_frames=3, shape_max_frames=2, shape_full_steps=2,
                     shape_iou_margin=1.0, coarse_factor=coarse_factor, coarse_steps=3)
    data = _data(clip_dir, config)
    seen = []
    original = objective.FitProblem.step_loss

    def record(problem, params, pyramid_weight, leaves, colour, colour_geometry):
        seen.append((problem.num_used, problem.data.viewport.width_px, colour_geometry))
        return original(problem, params, pyramid_weight, leaves, colour, colour_geometry)

    monkeypatch.setattr(objective.FitProblem, "step_loss", record)
    result = fit(data, config)
    stages = [h["stage"] for h in result.loss_history]
    native, coarse = data.viewport.width_px, data.viewport.width_px // coarse_factor
    assert stages == ["heading"] * 4 + ["global"] * 2 + ["body"] * 2 + ["shape"] * 5
    assert [n for n, _, _ in seen] == [3] * 4 + [data.num_frames] * 4 + [2, 2, 2] + [
        data.num_frames] * 2
    assert [w for _, w, _ in seen] == [coarse] * 7 + [native] * 6
    assert [c for _, _, c in seen] == [False] * 13   # colour_geometry "none", the default
    assert [h["step"] for h in result.loss_history] == [0, 1] * 2 + [0, 1] * 2 + list(range(5))
    # the colour term is read where something reads it: the heading trials compare totals,
    # the shape stage fits the appearance; the pose stages between are not shaded
    assert ["rgb" in h for h in result.loss_history] == [True] * 4 + [False] * 4 + [True] * 5
    assert np.isfinite(result.volume_m3) and result.iou.shape == (data.num_frames,)


def test_new_work_options_are_validated():
    for name in ("heading_max_frames", "shape_max_frames", "shape_full_steps", "coarse_steps"):
        with pytest.raises(Exception, match=name):
            FitConfig(**{name: -1})
    with pytest.raises(Exception, match="coarse_factor"):
        FitConfig(coarse_factor=0)
    with pytest.raises(Exception, match="soft_primitives"):
        FitConfig(soft_primitives="edges")
    with pytest.raises(Exception, match="colour_geometry"):
        FitConfig(colour_geometry="shape")


@pytest.mark.parametrize("choice, moves", [
    ("all_stages", (True, True, True)), ("pose_stages", (True, True, False)),
    ("none", (False, False, False))])
def test_colour_geometry_names_the_stages_where_colour_moves_the_geometry(choice, moves):
    config = FitConfig(colour_geometry=choice)
    assert tuple(config.colour_moves_geometry(s) for s in schedule.STAGES) == moves


def test_colour_term_kept_off_the_geometry_fits_only_the_appearance(clip_dir):
    """Without colour_geometry the meshes get the gradient of the other terms alone (that of
    a fit whose colour weight is 0) and albedo, water and light that of the colour term, the
    same as with it."""
    data = _data(clip_dir)
    template = load_template()
    model = DolphinModel(template)
    state = initial_state(data, model, 0.15)
    params = scene.initial_params(data, model, template, FitConfig(), state.heading_rad,
                                    state, silhouette_centroid_offset(model))
    leaves = [params.betas, params.albedo, params.f_water, params.light_amplitude]
    chunk = torch.tensor([0, 2, 4])

    def gradients(config, colour, colour_geometry):
        problem = objective.FitProblem(data, model, template, config, FitReporter(1, None), None)
        verts = problem.posed_verts(params, chunk).detach()
        _, vert_grad, grads, _ = problem.chunk_loss(params, chunk, verts, 2.0, leaves,
                                                    colour, colour_geometry)
        return vert_grad, grads

    with_colour, with_colour_grads = gradients(FitConfig(), True, True)
    kept_off, kept_off_grads = gradients(FitConfig(), True, False)
    no_colour, _ = gradients(FitConfig(weights=LossWeights(rgb=0.0)), True, True)
    unshaded, unshaded_grads = gradients(FitConfig(), False, False)
    assert float(with_colour.abs().max()) > 0
    torch.testing.assert_close(kept_off, no_colour, rtol=1e-5, atol=1e-9)
    # not shaded at all: the meshes get the same gradient, to the bit, the appearance none
    assert torch.equal(unshaded, kept_off)
    assert all(float(grad.abs().max()) == 0.0 for grad in unshaded_grads)
    assert not torch.allclose(kept_off, with_colour, rtol=1e-3, atol=1e-9)
    for off, on in zip(kept_off_grads[1:], with_colour_grads[1:]):
        assert float(on.abs().max()) > 0
        torch.testing.assert_close(off, on, rtol=1e-5, atol=1e-9)
    assert float(kept_off_grads[0].abs().max()) == 0.0   # shape moves only through meshes


def test_colour_loss_at_covered_pixels_equals_the_whole_image_formula(clip_dir):
    """Reading the colour loss at covered pixels only gives Σ_t mean over (covered ∧ mask)
    of the squared error computed over whole images, on frames of a chunk out of order."""
    data = _data(clip_dir)
    config = FitConfig()
    template = load_template()
    model = DolphinModel(template)
    problem = objective.FitProblem(data, model, template, config, FitReporter(1, None), None)
    state = initial_state(data, model, config.init_depth_m)
    params = scene.initial_params(data, model, template, config, state.heading_rad, state,
                                    silhouette_centroid_offset(model))
    chunk = torch.tensor([3, 0, 5])
    with torch.no_grad():
        out = problem.render_verts(params, chunk, problem.posed_verts(params, chunk))
        both = (out.coverage & (data.masks[chunk] > 0.5)).double()
        error = ((out.rgb.double() - data.images[chunk].double()) ** 2).sum(-1) * both
        expected = (error.sum((1, 2)) / both.sum((1, 2)).clamp(min=1.0)).sum()
        assert float(both.sum()) > 1000
        assert float(problem.rgb_term(out, chunk)) == pytest.approx(float(expected), rel=1e-5)


@pytest.mark.parametrize("frames, max_size, sizes", [
    (50, 16, [13, 13, 12, 12]), (16, 16, [8, 8]), (8, 64, [4, 4]), (17, 8, [5, 4, 4, 4]),
    (1, 16, [1]), (3, 1, [1, 1, 1])])
def test_frames_split_into_an_even_number_of_near_equal_chunks(frames, max_size, sizes):
    """The fewest chunks of at most max_size frames, rounded up to an even count where there
    are frames enough, consecutive and in order, sizes differing by one at most."""
    chunks = equal_chunks(torch.arange(frames), max_size)
    assert [len(c) for c in chunks] == sizes
    assert torch.equal(torch.cat(chunks), torch.arange(frames))
