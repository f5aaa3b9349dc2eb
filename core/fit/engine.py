"""The staged fit (DESIGN.md §6): global pose → body pose → shape, texture, water and light.

``fit`` is the one entry point for the CLI, the GUI worker, the benchmarks and the tests. It
tries both 180°-ambiguous headings for a few steps and keeps the better, fades a wide-basin
silhouette pyramid out over the first two stages and renders frames in chunks (bounded
memory; a cancel request is honoured between chunks). A fit that is cancelled, or whose loss
turns non-finite, ends early with the best state of the stage it was in: its result says so
in ``status`` and ``status_message``. Progress: core.fit.reporter.
"""

import math
import threading
import time
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, wait
from dataclasses import dataclass, fields
from functools import reduce

import numpy as np
import torch

from core.fit import losses
from core.fit.config import FitConfig
from core.fit.data import FitData, downscaled
from core.fit.init import initial_state, root_positions, silhouette_centroid_offset
from core.fit.reporter import (
    HEADING_STAGE, PREPARE_STAGE, RESULT_STAGE, FitPreview, FitReporter,
)
from core.fit.result import STATUS_CANCELLED, STATUS_COMPLETE, STATUS_DIVERGED, FitResult
from core.fit.target import edge_profile, soft_targets
from core.iou import mask_iou
from core.measure.condition import body_condition
from core.measure.hw_ratios import resolve_hw
from core.measure.mesh import body_length, mesh_volume
from core.model.lbs import axis_angle_to_matrix
from core.model.model import DolphinModel
from core.model.profile_field import NUM_KNOTS
from core.model.sections import NUM_TABLE_STATIONS, reshape_sections
from core.model.template import Template, load_template
from core.progress import Cancelled, ProgressCallback, check_cancel
from core.render.contour import mesh_edges
from core.render.pyramid import pyramid_loss, silhouette_pyramid
from core.render.render import Appearance, RenderOutput, render
from core.render.settings import RasterSettings, Viewport
from core.render.shade import SGLight
from core.runtime import single_thread_workers

STAGES = ("global", "body", "shape")   # what each optimises: see _stage_groups
STAGE_WORDS = {HEADING_STAGE: "heading", "global": "global pose", "body": "body pose",
               "shape": "shape"}
V_SURF_M_S = 6.6      # the paper's upward nudge while pointing up
V_DIVE_M_S = 2.2      # the paper's downward nudge while pointing down
INITIAL_F_WATER = 0.3
PROFILE_FRAMES = 4    # frames rendered to measure the renderer's edge profile
SMOOTH_REFERENCE_S = 1.0 / 25.0   # frame interval the smoothness weights refer to
# Mean fit IoU below which a fit is flagged: on the widened bench suite good masks gave
# 0.76–0.94 per clip, and masks of a seagrass patch or of glitter 0.56 (0.61 and 0.65 with
# the exhaustive fit).
POOR_FIT_IOU = 0.7
WAIT_S = 0.2          # how often the fit's thread checks cancel while workers render


class _Stop(Exception):
    """Ends the optimisation early; ``params`` hold the best state of the ``stage`` it ended
    in, whose loss was ``best_total``."""

    def __init__(self, status: str, reason: str, stage: str, best_total: float,
                 params: "SceneParams"):
        super().__init__(reason)
        self.status, self.reason, self.stage = status, reason, stage
        self.best_total, self.params = best_total, params


@dataclass
class SceneParams:
    """The tensors being optimised (DESIGN.md §6: θ, β, P, albedo, F_water, light)."""

    root_aa: torch.Tensor       # (T, 3)
    body_pose: torch.Tensor     # (T, M − 1, 3)
    transl: torch.Tensor        # (T, 3)
    log_scale: torch.Tensor     # () overall size, added to every part's uniform scale
    betas: torch.Tensor         # (M, 4) part shape around the overall size
    profile: torch.Tensor       # (2, K) profile field along the body (core.model.profile_field)
    albedo: torch.Tensor        # (Ht, Wt)
    f_water: torch.Tensor       # (3,)
    light_axes: torch.Tensor    # (K, 3)
    light_sharpness: torch.Tensor  # (K,)
    light_amplitude: torch.Tensor  # (K, 3)

    def tensors(self) -> dict[str, torch.Tensor]:
        """Name → tensor."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def snapshot(self) -> dict[str, torch.Tensor]:
        """Detached copies, to restore the best state."""
        return {name: t.detach().clone() for name, t in self.tensors().items()}

    def restore(self, snapshot: dict[str, torch.Tensor]) -> None:
        """Copy a snapshot back in place."""
        with torch.no_grad():
            for name, tensor in self.tensors().items():
                tensor.copy_(snapshot[name])

    def pose(self) -> torch.Tensor:
        """(T, M, 3) axis-angle per part."""
        return torch.cat([self.root_aa[:, None], self.body_pose], dim=1)

    def full_betas(self) -> torch.Tensor:
        """(M, 4) part log scales with the overall size."""
        return self.betas + torch.stack([self.log_scale] + [torch.zeros_like(self.log_scale)] * 3)

    def light(self) -> SGLight:
        """The light in its physical ranges."""
        return SGLight(self.light_axes / torch.linalg.vector_norm(self.light_axes, dim=-1,
                                                                  keepdim=True),
                       self.light_sharpness, self.light_amplitude)

    def project_to_valid(self) -> None:
        """Keep parameters in their domains after an optimiser step."""
        with torch.no_grad():
            self.albedo.clamp_(0.0, 1.0)
            self.f_water.clamp_(0.0, 1.0)
            self.light_sharpness.clamp_(min=0.05)
            self.light_amplitude.clamp_(min=0.0)
            self.light_axes.div_(torch.linalg.vector_norm(self.light_axes, dim=-1, keepdim=True))


def _initial_params(data: FitData, model: DolphinModel, template: Template, config: FitConfig,
                    heading: np.ndarray, state, offset_xy: np.ndarray) -> SceneParams:
    transl = root_positions(state, heading, offset_xy, config.init_depth_m)
    num_frames, num_groups = data.num_frames, model.num_groups
    root = np.zeros((num_frames, 3))
    root[:, 2] = heading
    light = SGLight.overhead_sun()
    tensors = dict(
        root_aa=torch.tensor(root, dtype=torch.float32),
        body_pose=torch.zeros(num_frames, num_groups - 1, 3),
        transl=torch.tensor(transl, dtype=torch.float32),
        log_scale=torch.tensor(state.log_scale, dtype=torch.float32),
        betas=torch.zeros(num_groups, 4),
        profile=torch.zeros(2, NUM_KNOTS),
        albedo=torch.tensor(template.albedo / 255.0, dtype=torch.float32),
        f_water=torch.full((3,), INITIAL_F_WATER),
        light_axes=light.axes.clone(), light_sharpness=light.sharpness.clone(),
        light_amplitude=light.amplitude.clone())
    return SceneParams(**{k: v.requires_grad_() for k, v in tensors.items()})


def _stage_groups(params: SceneParams, stage: str, config: FitConfig) -> list[dict]:
    """Adam parameter groups active in ``stage``, each with its learning rate."""
    lr = config.learning_rates
    groups = [{"params": [params.root_aa], "lr": lr.pose},
              {"params": [params.transl], "lr": lr.transl}]
    if stage in ("body", "shape"):
        groups.append({"params": [params.body_pose], "lr": lr.pose})
    if stage == "shape":
        # the overall size stays at its robust estimate from the masks until the frames the
        # pose stages cannot explain are set aside (dives would otherwise shrink it)
        shape = [params.log_scale, params.betas] + ([params.profile] if config.profile_field
                                                     else [])
        groups += [{"params": shape, "lr": lr.shape},
                   {"params": [params.albedo], "lr": lr.albedo},
                   {"params": [params.f_water], "lr": lr.water},
                   {"params": [params.light_axes, params.light_sharpness,
                               params.light_amplitude], "lr": lr.light}]
    return groups


class _Problem:
    """The data, model and fixed inputs one fit evaluates its parameters against; chunks of
    frames are rendered in ``pool``'s threads where there is one."""

    def __init__(self, data: FitData, model: DolphinModel, template: Template,
                 config: FitConfig, reporter: FitReporter, cancel: threading.Event | None,
                 pool: Executor | None = None, chunk_frames: int | None = None):
        self.data, self.model, self.config = data, model, config
        self.reporter, self.cancel, self.pool = reporter, cancel, pool
        self.chunk_frames = chunk_frames or config.frames_per_chunk
        self.template = template
        self.settings = RasterSettings(max_faces_per_pixel=config.max_faces_per_pixel,
                                       soft_primitives=config.soft_primitives)
        self.edges = mesh_edges(model.faces)
        self.face_uvs = torch.tensor(template.uvs[template.face_uvs_idx], dtype=torch.float32)
        self.time_s = torch.as_tensor(data.time_s, dtype=torch.float32)
        interval = float(np.median(np.diff(data.time_s))) if data.num_frames > 1 else 1.0
        self.frame_ratio = SMOOTH_REFERENCE_S / interval
        self.set_targets(data.masks)
        self.use_all_frames()

    def set_targets(self, targets: torch.Tensor) -> None:
        """Fit to soft ``targets`` (T, H, W); their pyramid is computed once here."""
        self.targets = targets
        with torch.no_grad():
            self.target_pyramid = silhouette_pyramid(targets)

    def use_all_frames(self) -> None:
        """Render every frame in each step."""
        self.set_frames(torch.arange(self.data.num_frames))

    def set_frames(self, frames: torch.Tensor) -> None:
        """Render only ``frames`` in each step, in chunks."""
        self.frames = frames
        self.chunks = equal_chunks(frames, self.chunk_frames)
        self.num_used = len(frames)

    def map_chunks(self, work: Callable[[object], object], chunks: Sequence,
                   cancellable: bool = True) -> list:
        """``work(chunk)`` for each chunk, in order, in the pool's threads where there is
        one; between chunks the heartbeat is kept and, if ``cancellable``, the cancel
        request honoured."""
        cancel = self.cancel if cancellable else None
        if self.pool is None:
            results = []
            for chunk in chunks:
                check_cancel(cancel)
                self.reporter.heartbeat()
                results.append(work(chunk))
            return results
        check_cancel(cancel)
        futures = [self.pool.submit(work, chunk) for chunk in chunks]
        try:
            while wait(futures, timeout=WAIT_S).not_done:
                check_cancel(cancel)
                self.reporter.heartbeat()
        except Cancelled:
            for future in futures:
                future.cancel()
            wait(futures)
            raise
        return [future.result() for future in futures]

    def frame_ious(self, params: SceneParams) -> torch.Tensor:
        """(T,) hard IoU of every frame at ``params``."""
        def work(chunk: torch.Tensor) -> torch.Tensor:
            with torch.no_grad():   # grad mode is per thread
                return mask_iou(self.render_chunk(params, chunk).coverage,
                                self.data.masks[chunk] > 0.5)

        chunks = equal_chunks(torch.arange(self.data.num_frames), self.chunk_frames)
        return torch.cat(self.map_chunks(work, chunks, cancellable=False))

    def restrict_to_explained_frames(self, params: SceneParams) -> list[str]:
        """Keep for the shape stage the frames the pose stages explain (config doc)."""
        iou = self.frame_ious(params)
        keep = iou >= float(iou.median()) - self.config.shape_iou_margin
        self.set_frames(torch.nonzero(keep)[:, 0])
        dropped = self.data.frame_idx[(~keep).numpy()]
        if len(dropped) == 0:
            return []
        return [f"{len(dropped)} of {len(iou)} frames left out of the shape stage (IoU after "
                f"the pose stages below the median {float(iou.median()):.3f} − "
                f"{self.config.shape_iou_margin}): frames {', '.join(map(str, dropped[:8]))}"
                + (" …" if len(dropped) > 8 else "")]

    def profile(self, params: SceneParams) -> torch.Tensor | None:
        """The profile field's coefficients, None when the configuration has no field."""
        return params.profile if self.config.profile_field else None

    def posed_verts(self, params: SceneParams, frames: torch.Tensor) -> torch.Tensor:
        """(len(frames), V, 3) posed meshes of ``frames`` at ``params``."""
        return self.model(params.full_betas(), params.pose()[frames],
                          params.transl[frames], self.profile(params)).verts

    def render_chunk(self, params: SceneParams, chunk: torch.Tensor) -> RenderOutput:
        """Render frames ``chunk`` at ``params``."""
        return self.render_verts(params, chunk, self.posed_verts(params, chunk))

    def render_verts(self, params: SceneParams, chunk: torch.Tensor,
                     verts: torch.Tensor) -> RenderOutput:
        """Render the posed meshes ``verts`` (len(chunk), V, 3) of frames ``chunk``."""
        appearance = Appearance(params.albedo, self.face_uvs, params.light(), params.f_water)
        viewport = Viewport(self.data.viewport.x0_px[chunk], self.data.viewport.y0_px[chunk],
                            self.data.viewport.width_px, self.data.viewport.height_px)
        return render(verts, self.model.faces, appearance, self.data.camera.select(chunk),
                      viewport, self.settings, self.edges)

    def step_loss(self, params: SceneParams, pyramid_weight: float,
                  leaves: list[torch.Tensor], colour_geometry: bool
                  ) -> tuple[dict, torch.Tensor]:
        """Set the gradients of ``leaves`` (the parameters being optimised: autograd skips
        what only the others need) to those of the total loss, the colour term's on the
        geometry only with ``colour_geometry``; returns term values and per-frame IoU.

        The model poses every frame of the step at once, here; the chunks render their
        frames' meshes as their own leaves and return the gradients of the loss for them,
        which go back through the model once. Gradients are summed in chunk order.
        """
        posed = self.posed_verts(params, self.frames)
        meshes = posed.detach().split([len(chunk) for chunk in self.chunks])
        chunks = self.map_chunks(
            lambda item: self.chunk_loss(params, *item, pyramid_weight, leaves,
                                         colour_geometry),
            list(zip(self.chunks, meshes)))
        weights = self.config.weights
        prior_terms = self.prior_terms(params)
        prior_total = sum(getattr(weights, name) * value for name, value in prior_terms.items())
        grads = [*(grads for _, _, grads, _ in chunks),
                 torch.autograd.grad(posed, leaves, torch.cat([g for _, g, _, _ in chunks]),
                                     materialize_grads=True),
                 torch.autograd.grad(prior_total, leaves, materialize_grads=True)]
        for leaf, parts in zip(leaves, zip(*grads)):
            leaf.grad = reduce(torch.add, parts)
        terms = {name: sum(chunk_terms[name] for chunk_terms, _, _, _ in chunks)
                 for name in ("mask", "rgb", "pyramid", "total")}
        terms.update({name: float(value.detach()) for name, value in prior_terms.items()})
        terms["total"] += float(prior_total.detach())
        return terms, torch.cat([iou for _, _, _, iou in chunks])

    def chunk_loss(self, params: SceneParams, chunk: torch.Tensor, verts: torch.Tensor,
                   pyramid_weight: float, leaves: list[torch.Tensor],
                   colour_geometry: bool
                   ) -> tuple[dict[str, float], torch.Tensor, tuple[torch.Tensor, ...],
                              torch.Tensor]:
        """One chunk's loss terms, the gradients of its total for its posed meshes ``verts``
        (detached; without the colour term's unless ``colour_geometry``) and for ``leaves``,
        and its frames' IoU (thread-safe: it changes nothing shared)."""
        weights = self.config.weights
        num_frames = self.num_used
        verts = verts.requires_grad_()
        out = self.render_verts(params, chunk, verts)
        mask_term = losses.soft_iou_loss(out.soft_mask, self.targets[chunk]) / num_frames
        rgb_term = self.rgb_term(out, chunk) / num_frames
        total = weights.mask * mask_term + weights.rgb * rgb_term
        terms = {"mask": float(mask_term.detach()), "rgb": float(rgb_term.detach()),
                 "pyramid": 0.0}
        if pyramid_weight > 0:
            pyramid_term = (pyramid_loss(out.soft_mask, [level[chunk] for level in
                                                         self.target_pyramid])
                            * len(chunk) / num_frames)
            total = total + pyramid_weight * pyramid_term
            terms["pyramid"] = float(pyramid_term.detach())
        terms["total"] = float(total.detach())
        if colour_geometry:
            vert_grad, *grads = torch.autograd.grad(total, [verts, *leaves],
                                                    materialize_grads=True)
        else:   # the meshes are the only way to the geometry: the colour term skips them
            colour = weights.rgb * rgb_term
            vert_grad, *grads = torch.autograd.grad(total - colour, [verts, *leaves],
                                                    retain_graph=True, materialize_grads=True)
            grads = map(torch.add, grads,
                        torch.autograd.grad(colour, leaves, materialize_grads=True))
        return terms, vert_grad, tuple(grads), mask_iou(out.coverage,
                                                       self.data.masks[chunk] > 0.5)

    def rgb_term(self, out: RenderOutput, chunk: torch.Tensor) -> torch.Tensor:
        """The colour loss of a chunk's render, read at its covered pixels only."""
        pixels = self.data.viewport.num_pixels
        local_frame = torch.div(out.pixel, pixels, rounding_mode="floor")
        at = chunk[local_frame] * pixels + out.pixel % pixels
        return losses.rgb_loss(out.pixel_rgb, local_frame,
                               self.data.images.reshape(-1, 3)[at],
                               self.data.masks.reshape(-1)[at], len(chunk))

    def prior_terms(self, params: SceneParams) -> dict[str, torch.Tensor]:
        order = self.config.smooth_order
        ratio = self.frame_ratio
        rotations = axis_angle_to_matrix(params.root_aa)
        terms = {
            "pose": losses.pose_prior(params.body_pose),
            "scale": losses.scale_prior(params.betas),
            "scale_axes": losses.scale_axes_prior(params.betas),
            "scale_smooth": losses.scale_smooth_prior(params.betas, self.model.group_parents),
            "smooth_pos": losses.smoothness(params.transl, order, ratio),
            "smooth_rot": losses.rotation_smoothness(rotations, order, ratio),
            "smooth_pose": losses.smoothness(params.body_pose, order, ratio),
            "depth": losses.depth_prior(params.transl, self.config.init_depth_m),
            "glide": losses.glide_prior(params.transl, rotations[:, :, 0], self.time_s),
        }
        if self.config.profile_field:
            terms["profile"] = losses.profile_prior(params.profile)
            terms["profile_smooth"] = losses.profile_smoothness(params.profile)
        if self.config.use_vertical_prior:
            terms["vertical"] = losses.vertical_motion(params.transl, rotations[:, 2, 0],
                                                       self.time_s, V_SURF_M_S, V_DIVE_M_S)
        if self.config.use_direction_loss:
            terms["direction"] = losses.direction_loss(rotations[:, :2, 0], params.transl)
        return terms


def fitted_template(template: Template, config: FitConfig) -> Template:
    """The template the fit shapes: with its hidden heights from ``config.hw_table`` (an
    InputError names a table that cannot be read)."""
    if config.hw_table is None:
        return template
    ratios = resolve_hw(config.hw_table).ratios[:NUM_TABLE_STATIONS]
    return reshape_sections(template, ratios)


def fit(data: FitData, config: FitConfig = FitConfig(), template: Template | None = None, *,
        progress: ProgressCallback | None = None,
        cancel: threading.Event | None = None) -> FitResult:
    """Fit the model to ``data``; deterministic for the same inputs and configuration, to
    the last bit whatever torch's thread count: chunks of frames run on as many worker
    threads, one torch thread each (core.runtime.single_thread_workers).

    Once ``cancel`` is set the fit returns the best state reached with status "cancelled";
    before the first optimisation step there is nothing to keep and it raises Cancelled.
    """
    with single_thread_workers(torch.get_num_threads()) as pool:
        return _fit(data, config, template, progress, cancel, pool)


def _fit(data: FitData, config: FitConfig, template: Template | None,
         progress: ProgressCallback | None, cancel: threading.Event | None,
         pool: Executor | None) -> FitResult:
    started = time.perf_counter()
    reporter = FitReporter(config.total_steps, progress)
    reporter.report(PREPARE_STAGE, "placing the model")
    template = fitted_template(template if template is not None else load_template(), config)
    model = DolphinModel(template)
    problem = _Problem(data, model, template, config, reporter, cancel, pool)
    state = initial_state(data, model, config.init_depth_m)
    timings: dict[str, float] = {}
    history: list[dict] = []
    offset_xy = silhouette_centroid_offset(model)
    candidates = [_initial_params(data, model, template, config, state.heading_rad + flip,
                                  state, offset_xy) for flip in (0.0, math.pi)]
    problem.set_targets(_debiased_targets(problem, candidates[0]))
    coarse = _coarse_problem(problem, candidates[0])
    timings["setup"] = time.perf_counter() - started
    warnings = list(data.warnings)
    status, message = STATUS_COMPLETE, ""
    try:
        params = _choose_heading(coarse, candidates, history, timings)
        fade_steps = max(1, config.steps_global + config.steps_body)
        done = 0
        for stage, steps in zip(STAGES, (config.steps_global, config.steps_body,
                                         config.steps_shape)):
            stage_started = time.perf_counter()
            fade = lambda k, o=done: max(0.0, 1.0 - (o + k) / fade_steps)  # noqa: E731
            if stage == "shape":
                warnings += problem.restrict_to_explained_frames(params)
                parts = _shape_parts(problem, steps)
            else:
                at_coarse = min(steps, max(0, config.coarse_steps - done))
                every = torch.arange(data.num_frames)
                parts = [(coarse, every, at_coarse), (problem, every, steps - at_coarse)]
            _run_in_parts(params, stage, parts, fade, history)
            done += steps
            timings[stage] = time.perf_counter() - stage_started
    except _Stop as stop:
        if stop.status == STATUS_CANCELLED and reporter.step == 0:
            raise Cancelled() from None
        params, status = stop.params, stop.status
        message = _stop_message(stop, reporter)
    timings["total"] = time.perf_counter() - started
    problem.use_all_frames()
    reporter.report(RESULT_STAGE, "building the meshes")
    result = _result(problem, params, history, timings, tuple(warnings), status, message)
    reporter.report(RESULT_STAGE, message or "done")
    return result


def _coarse_problem(problem: _Problem, params: SceneParams) -> _Problem:
    """The problem at 1/``coarse_factor`` resolution (itself where that is 1 or the windows
    do not allow it), with targets debiased at that resolution."""
    coarse_data = (downscaled(problem.data, problem.config.coarse_factor)
                   if problem.config.coarse_factor > 1 else None)
    if coarse_data is None:
        return problem
    # as many pixels a chunk as at native resolution
    coarse = _Problem(coarse_data, problem.model, problem.template, problem.config,
                      problem.reporter, problem.cancel, problem.pool,
                      problem.chunk_frames * problem.config.coarse_factor ** 2)
    coarse.set_targets(_debiased_targets(coarse, params))
    return coarse


def _choose_heading(problem: _Problem, candidates: list[SceneParams], history: list[dict],
                    timings: dict[str, float]) -> SceneParams:
    """Fit both headings for a few steps and keep the one with the lower loss."""
    trial_started = time.perf_counter()
    trials = []
    problem.set_frames(evenly_spaced(torch.arange(problem.data.num_frames),
                                     problem.config.heading_max_frames))
    try:
        for candidate in candidates:
            last_total = _run_stage(problem, candidate, "global",
                                    problem.config.heading_trial_steps, lambda k: 1.0, history,
                                    label=HEADING_STAGE)
            trials.append((last_total, candidate))
    except _Stop as stop:
        trials.append((stop.best_total, stop.params))
        stop.params = min(trials, key=lambda item: item[0])[1]
        raise
    timings[HEADING_STAGE] = time.perf_counter() - trial_started
    return min(trials, key=lambda item: item[0])[1]


def equal_chunks(frames: torch.Tensor, max_size: int) -> list[torch.Tensor]:
    """``frames`` in consecutive chunks of at most ``max_size`` frames, of sizes that differ
    by one at most: the fewest such chunks, rounded up to an even number (where there are
    frames enough), so that two workers share any step evenly. The rule does not depend on
    the number of workers, so neither do the results."""
    count = math.ceil(len(frames) / max_size)
    count = max(1, min(len(frames), count + count % 2))
    return list(torch.tensor_split(frames, count))


def evenly_spaced(frames: torch.Tensor, limit: int) -> torch.Tensor:
    """At most ``limit`` of ``frames`` (all of them for 0), spread evenly from first to last."""
    if limit <= 0 or len(frames) <= limit:
        return frames
    return frames[torch.linspace(0, len(frames) - 1, limit).round().to(torch.int64)]


def _shape_parts(problem: _Problem, steps: int) -> list[tuple["_Problem", torch.Tensor, int]]:
    """The shape stage on at most ``shape_max_frames`` of the frames chosen for it, then on
    all of them for its last ``shape_full_steps`` steps, so that every frame's pose catches up
    with the shape."""
    chosen = problem.frames
    subset = evenly_spaced(chosen, problem.config.shape_max_frames)
    full_steps = steps if len(subset) == len(chosen) else min(steps,
                                                              problem.config.shape_full_steps)
    return [(problem, subset, steps - full_steps), (problem, chosen, full_steps)]


def _run_in_parts(params: SceneParams, stage: str,
                  parts: list[tuple["_Problem", torch.Tensor, int]],
                  pyramid_fade: Callable[[int], float], history: list[dict]) -> None:
    """One stage, one optimiser, in consecutive parts: each renders its problem's (its
    resolution's) frames for its number of steps."""
    optimiser = torch.optim.Adam(_stage_groups(params, stage, parts[0][0].config))
    done = 0
    for problem, frames, steps in parts:
        if steps == 0:
            continue
        problem.set_frames(frames)
        _run_stage(problem, params, stage, steps, lambda k, o=done: pyramid_fade(o + k),
                   history, optimiser=optimiser, first_step=done)
        done += steps


def _stop_message(stop: _Stop, reporter: FitReporter) -> str:
    """What an early end means, e.g. "cancelled by the user after 40 of 175 steps (global
    pose unfinished; body pose, shape not fitted)"."""
    order = (HEADING_STAGE, *STAGES)
    later = [STAGE_WORDS[s] for s in order[order.index(stop.stage) + 1:]]
    missing = f"; {', '.join(later)} not fitted" if later else ""
    return (f"{stop.reason} after {reporter.step} of {reporter.total} steps "
            f"({STAGE_WORDS[stop.stage]} unfinished{missing}); the best state of that stage "
            f"is kept")


def _run_stage(problem: _Problem, params: SceneParams, stage: str, steps: int,
               pyramid_fade: Callable[[int], float], history: list[dict],
               label: str | None = None, optimiser: torch.optim.Optimizer | None = None,
               first_step: int = 0) -> float:
    """Optimise ``stage``'s parameters for ``steps`` (with ``optimiser``, a fresh Adam over
    the stage's groups by default); returns the last step's loss. On a cancel or a non-finite
    loss restore the best state of this run (losses of one run share their weights and
    frames, so they compare) and raise _Stop. ``first_step`` numbers the steps in history."""
    label = label or stage
    if optimiser is None:
        optimiser = torch.optim.Adam(_stage_groups(params, stage, problem.config))
    problem.reporter.preview_source = lambda: _preview(problem, params)
    best_total, best = math.inf, params.snapshot()
    total = math.inf
    leaves = [leaf for group in optimiser.param_groups for leaf in group["params"]]
    colour_geometry = problem.config.colour_moves_geometry(stage)
    for k in range(steps):
        weight = problem.config.weights.pyramid * pyramid_fade(k)
        problem.reporter.step_started()
        try:
            terms, iou = problem.step_loss(params, weight, leaves, colour_geometry)
        except Cancelled:
            params.restore(best)
            raise _Stop(STATUS_CANCELLED, "cancelled by the user", label, best_total,
                        params) from None
        if not math.isfinite(terms["total"]):
            params.restore(best)
            raise _Stop(STATUS_DIVERGED, f"the loss became non-finite at step "
                        f"{first_step + k + 1} of the "
                        f"{label} stage", label, best_total, params)
        total = terms["total"]
        if total < best_total:
            best_total, best = total, params.snapshot()
        optimiser.step()
        params.project_to_valid()
        mean_iou = float(iou.float().mean())
        history.append({"stage": label, "step": first_step + k, **terms,
                        "mean_iou": mean_iou})
        problem.reporter.step_done(label, terms, mean_iou)
    return total


def _preview(problem: _Problem, params: SceneParams) -> FitPreview:
    """The posed meshes of the current state, for display while the fit runs."""
    with torch.no_grad():
        posed = problem.model(params.full_betas(), params.pose(), params.transl,
                              problem.profile(params)).verts
    return FitPreview(frame_idx=problem.data.frame_idx, posed_verts=posed.numpy().copy())


def _debiased_targets(problem: _Problem, params: SceneParams) -> torch.Tensor:
    """Soft targets with the renderer's edge profile, measured on the initial model."""
    with torch.no_grad():
        chunk = torch.arange(min(PROFILE_FRAMES, problem.data.num_frames))
        out = problem.render_chunk(params, chunk)
    profile = edge_profile(out.soft_mask, out.coverage)
    return soft_targets(problem.data.masks, profile, problem.config.target_edge_scale)


def quality_warnings(ious: np.ndarray) -> tuple[str, ...]:
    """A warning when the fitted model explains its masks poorly (mean IoU below
    ``POOR_FIT_IOU``): the masks may not show a dolphin at all (a seagrass patch, glitter),
    and a fit of them must not pass as a good one."""
    mean = float(np.mean(ious)) if len(ious) else 0.0
    if mean >= POOR_FIT_IOU:
        return ()
    return (f"poor fit: the model explains the masks with a mean IoU of {mean:.2f} (below "
            f"{POOR_FIT_IOU:.2f}); check that the masks show the dolphin, the figures are "
            f"unreliable",)


def _result(problem: _Problem, params: SceneParams, history: list[dict],
            timings: dict[str, float], warnings: tuple[str, ...], status: str,
            status_message: str) -> FitResult:
    model = DolphinModel(problem.template, dtype=torch.float64)
    profile = problem.profile(params)
    profile = None if profile is None else profile.detach().double()
    with torch.no_grad():
        betas = params.full_betas().double()
        rest, _ = model.forward_rest(betas, profile)
        posed = model(betas, params.pose().double(), params.transl.double(), profile).verts
        volume = float(mesh_volume(rest, model.faces))
        length = float(body_length(rest, model.rostrum_idx, model.notch_idx))
    ious = problem.frame_ious(params)
    warnings = warnings + quality_warnings(ious.double().numpy())
    condition = body_condition(np.float64(length), np.float64(volume))
    return FitResult(
        betas=betas.numpy(), profile=None if profile is None else profile.numpy(),
        pose_aa=params.pose().detach().double().numpy(),
        transl=params.transl.detach().double().numpy(), frame_idx=problem.data.frame_idx,
        time_s=problem.data.time_s, iou=ious.double().numpy(), rest_verts=rest.numpy(),
        posed_verts=posed.numpy(), faces=model.faces.numpy(),
        albedo=_float64(params.albedo), f_water=_float64(params.f_water),
        light={"axes": _float64(params.light().axes),
               "sharpness": _float64(params.light_sharpness),
               "amplitude": _float64(params.light_amplitude)},
        volume_m3=volume, length_m=length, bci=float(condition.bci),
        mass_kg=float(condition.mass_kg), density_kg_m3=float(condition.density_kg_m3),
        loss_history=tuple(history), timings_s=timings, config=problem.config,
        warnings=warnings, status=status, status_message=status_message)


def _float64(tensor: torch.Tensor) -> np.ndarray:
    return tensor.detach().double().numpy()
