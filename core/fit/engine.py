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
from concurrent.futures import Executor

import numpy as np
import torch

from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.data import FitData
from dolphinfit.core.fit.init import initial_state, silhouette_centroid_offset
from dolphinfit.core.fit.objective import FitProblem
from dolphinfit.core.fit.reporter import PREPARE_STAGE, RESULT_STAGE, FitReporter
from dolphinfit.core.fit.reliability import unreliable_reasons
from dolphinfit.core.fit.result import (
    STATUS_CANCELLED, STATUS_COMPLETE, STATUS_UNRELIABLE, FitResult,
)
from dolphinfit.core.fit.scene import SceneParams, initial_params
from dolphinfit.core.fit.schedule import (
    STAGES, Stop, choose_heading, coarse_problem, debiased_targets, run_in_parts, shape_parts,
    stop_message,
)
from dolphinfit.core.measure.condition import body_condition
from dolphinfit.core.model.hw_spec import resolve_hw
from dolphinfit.core.measure.mesh import body_length, mesh_volume
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.sections import NUM_TABLE_STATIONS, reshape_sections
from dolphinfit.core.model.template import Template, load_template
from dolphinfit.core.progress import Cancelled, ProgressCallback
from dolphinfit.core.runtime import single_thread_workers

# Mean fit IoU below which a fit is flagged: on the widened bench suite good masks gave
# 0.76–0.94 per clip, and masks of a seagrass patch or of glitter 0.56 (0.61 and 0.65 with
# the exhaustive fit).


def fitted_template(template: Template, config: FitConfig) -> Template:
    """The template the fit shapes: with its hidden heights from ``config.hw_table`` (an
    InputError names a table that cannot be read)."""
    if config.hw_table is None:
        return template
    ratios = resolve_hw(config.hw_table).ratios[:NUM_TABLE_STATIONS]
    return reshape_sections(template, ratios)


def fit(data: FitData, config: FitConfig = FitConfig(), template: Template | None = None, *,
        progress: ProgressCallback | None = None, cancel: threading.Event | None = None,
        device: torch.device | str = "cpu") -> FitResult:
    """Fit the model to ``data``; deterministic for the same inputs and configuration, to
    the last bit whatever torch's thread count: chunks of frames run on as many worker
    threads, one torch thread each (core.runtime.single_thread_workers).

    The data, the model and the parameters live on ``device`` (core.device) while the fit
    runs; the result is built on the CPU, in float64, wherever the fit ran. On a GPU two runs
    agree within float rounding only: its scatters add in no fixed order.

    Once ``cancel`` is set the fit returns the best state reached with status "cancelled";
    before the first optimisation step there is nothing to keep and it raises Cancelled.
    """
    with single_thread_workers(torch.get_num_threads()) as pool:
        return _fit(data.to(device), config, template, progress, cancel, pool)


def _fit(data: FitData, config: FitConfig, template: Template | None,
         progress: ProgressCallback | None, cancel: threading.Event | None,
         pool: Executor | None) -> FitResult:
    started = time.perf_counter()
    reporter = FitReporter(config.total_steps, progress)
    reporter.report(PREPARE_STAGE, "placing the model")
    template = fitted_template(template if template is not None else load_template(), config)
    model = DolphinModel(template).to(data.device)
    problem = FitProblem(data, model, template, config, reporter, cancel, pool)
    state = initial_state(data, model, config.init_depth_m)
    timings: dict[str, float] = {}
    history: list[dict] = []
    offset_xy = silhouette_centroid_offset(model)
    candidates = [initial_params(data, model, template, config, state.heading_rad + flip,
                                  state, offset_xy) for flip in (0.0, math.pi)]
    problem.set_targets(debiased_targets(problem, candidates[0]))
    coarse = coarse_problem(problem, candidates[0])
    timings["setup"] = time.perf_counter() - started
    warnings = list(data.warnings)
    status, message = STATUS_COMPLETE, ""
    try:
        params = choose_heading(coarse, candidates, history, timings)
        fade_steps = max(1, config.steps_global + config.steps_body)
        done = 0
        for stage, steps in zip(STAGES, (config.steps_global, config.steps_body,
                                         config.steps_shape)):
            stage_started = time.perf_counter()
            fade = lambda k, o=done: max(0.0, 1.0 - (o + k) / fade_steps)  # noqa: E731
            if stage == "shape":
                warnings += problem.restrict_to_explained_frames(params)
                parts = shape_parts(problem, steps)
            else:
                at_coarse = min(steps, max(0, config.coarse_steps - done))
                every = data.every_frame()
                parts = [(coarse, every, at_coarse), (problem, every, steps - at_coarse)]
            run_in_parts(params, stage, parts, fade, history)
            done += steps
            timings[stage] = time.perf_counter() - stage_started
    except Stop as stop:
        if stop.status == STATUS_CANCELLED and reporter.step == 0:
            raise Cancelled() from None
        params, status = stop.params, stop.status
        message = stop_message(stop, reporter)
    timings["total"] = time.perf_counter() - started
    problem.use_all_frames()
    reporter.report(RESULT_STAGE, "building the meshes")
    result = _result(problem, params, history, timings, tuple(warnings), status, message)
    reporter.report(RESULT_STAGE, message or "done")
    return result


def _result(problem: FitProblem, params: SceneParams, history: list[dict],
            timings: dict[str, float], warnings: tuple[str, ...], status: str,
            status_message: str) -> FitResult:
    model = DolphinModel(problem.template, dtype=torch.float64)   # on the CPU
    profile = problem.profile(params)
    profile = None if profile is None else profile.detach().double().cpu()
    with torch.no_grad():
        betas = params.full_betas().double().cpu()
        rest, _ = model.forward_rest(betas, profile)
        posed = model(betas, params.pose().double().cpu(), params.transl.double().cpu(),
                      profile).verts
        volume = float(mesh_volume(rest, model.faces))
        length = float(body_length(rest, model.rostrum_idx, model.notch_idx))
    ious = problem.frame_ious(params).cpu()
    data = problem.data
    reasons = unreliable_reasons(data.num_frames, ious.double().numpy(), data.elongation,
                                 data.animal_width_px)
    if status == STATUS_COMPLETE and reasons:
        status, status_message = STATUS_UNRELIABLE, "; ".join(reasons)
    condition = body_condition(np.float64(length), np.float64(volume))
    return FitResult(
        betas=betas.numpy(), profile=None if profile is None else profile.numpy(),
        pose_aa=_float64(params.pose()), transl=_float64(params.transl),
        frame_idx=problem.data.frame_idx,
        time_s=problem.data.time_s, iou=ious.double().numpy(), rest_verts=rest.numpy(),
        posed_verts=posed.numpy(), faces=model.faces.numpy(),
        albedo=_float64(params.albedo), f_water=_float64(params.f_water),
        light={"axes": _float64(params.light().axes),
               "sharpness": _float64(params.light_sharpness),
               "amplitude": _float64(params.light_amplitude)},
        volume_m3=volume, length_m=length, bci=float(condition.bci),
        mass_kg=float(condition.mass_kg), density_kg_m3=float(condition.density_kg_m3),
        loss_history=tuple(history), timings_s=timings, config=problem.config,
        warnings=warnings, status=status, status_message=status_message, reasons=reasons)


def _float64(tensor: torch.Tensor) -> np.ndarray:
    return tensor.detach().double().cpu().numpy()
