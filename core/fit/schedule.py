"""How a fit runs its stages: the heading trial, each stage's optimiser over its parts
(coarse, then native resolution; the shape stage on a subset of frames, then on all), the
targets debiased to the renderer's edge, and an early end (cancel, a non-finite loss) that
keeps the best state of the stage it was in."""

import math
import time
from collections.abc import Callable

import numpy as np
import torch

from dolphinfit.core.fit.data import downscaled
from dolphinfit.core.fit.objective import FitProblem, evenly_spaced
from dolphinfit.core.fit.reporter import HEADING_STAGE, FitPreview, FitReporter
from dolphinfit.core.fit.result import STATUS_CANCELLED, STATUS_DIVERGED
from dolphinfit.core.fit.scene import SceneParams, fits_appearance, stage_groups
from dolphinfit.core.fit.target import edge_profile, soft_targets
from dolphinfit.core.progress import Cancelled

STAGES = ("global", "body", "shape")   # what each optimises: see scene.stage_groups
STAGE_WORDS = {HEADING_STAGE: "heading", "global": "global pose", "body": "body pose",
               "shape": "shape"}
PROFILE_FRAMES = 4    # frames rendered to measure the renderer's edge profile


class Stop(Exception):
    """Ends the optimisation early; ``params`` hold the best state of the ``stage`` it ended
    in, whose loss was ``best_total``."""

    def __init__(self, status: str, reason: str, stage: str, best_total: float,
                 params: "SceneParams"):
        super().__init__(reason)
        self.status, self.reason, self.stage = status, reason, stage
        self.best_total, self.params = best_total, params


def coarse_problem(problem: FitProblem, params: SceneParams) -> FitProblem:
    """The problem at 1/``coarse_factor`` resolution (itself where that is 1 or the windows
    do not allow it), with targets debiased at that resolution."""
    coarse_data = (downscaled(problem.data, problem.config.coarse_factor)
                   if problem.config.coarse_factor > 1 else None)
    if coarse_data is None:
        return problem
    # as many pixels a chunk as at native resolution
    coarse = FitProblem(coarse_data, problem.model, problem.template, problem.config,
                      problem.reporter, problem.cancel, problem.pool,
                      problem.chunk_frames * problem.config.coarse_factor ** 2)
    coarse.set_targets(debiased_targets(coarse, params))
    return coarse


def choose_heading(problem: FitProblem, candidates: list[SceneParams], history: list[dict],
                    timings: dict[str, float]) -> SceneParams:
    """Fit both headings for a few steps and keep the one with the lower loss."""
    trial_started = time.perf_counter()
    trials = []
    problem.set_frames(evenly_spaced(problem.data.every_frame(),
                                     problem.config.heading_max_frames))
    try:
        for candidate in candidates:
            last_total = run_stage(problem, candidate, "global",
                                    problem.config.heading_trial_steps, lambda k: 1.0, history,
                                    label=HEADING_STAGE)
            trials.append((last_total, candidate))
    except Stop as stop:
        trials.append((stop.best_total, stop.params))
        stop.params = min(trials, key=lambda item: item[0])[1]
        raise
    timings[HEADING_STAGE] = time.perf_counter() - trial_started
    return min(trials, key=lambda item: item[0])[1]


def shape_parts(problem: FitProblem, steps: int) -> list[tuple["FitProblem", torch.Tensor, int]]:
    """The shape stage on at most ``shape_max_frames`` of the frames chosen for it, then on
    all of them for its last ``shape_full_steps`` steps, so that every frame's pose catches up
    with the shape."""
    chosen = problem.frames
    subset = evenly_spaced(chosen, problem.config.shape_max_frames)
    full_steps = steps if len(subset) == len(chosen) else min(steps,
                                                              problem.config.shape_full_steps)
    return [(problem, subset, steps - full_steps), (problem, chosen, full_steps)]


def run_in_parts(params: SceneParams, stage: str,
                  parts: list[tuple["FitProblem", torch.Tensor, int]],
                  pyramid_fade: Callable[[int], float], history: list[dict]) -> None:
    """One stage, one optimiser, in consecutive parts: each renders its problem's (its
    resolution's) frames for its number of steps."""
    optimiser = torch.optim.Adam(stage_groups(params, stage, parts[0][0].config))
    done = 0
    for problem, frames, steps in parts:
        if steps == 0:
            continue
        problem.set_frames(frames)
        run_stage(problem, params, stage, steps, lambda k, o=done: pyramid_fade(o + k),
                   history, optimiser=optimiser, first_step=done)
        done += steps


def stop_message(stop: Stop, reporter: FitReporter) -> str:
    """What an early end means, e.g. "cancelled by the user after 40 of 175 steps (global
    pose unfinished; body pose, shape not fitted)"."""
    order = (HEADING_STAGE, *STAGES)
    later = [STAGE_WORDS[s] for s in order[order.index(stop.stage) + 1:]]
    missing = f"; {', '.join(later)} not fitted" if later else ""
    return (f"{stop.reason} after {reporter.step} of {reporter.total} steps "
            f"({STAGE_WORDS[stop.stage]} unfinished{missing}); the best state of that stage "
            f"is kept")


def run_stage(problem: FitProblem, params: SceneParams, stage: str, steps: int,
               pyramid_fade: Callable[[int], float], history: list[dict],
               label: str | None = None, optimiser: torch.optim.Optimizer | None = None,
               first_step: int = 0) -> float:
    """Optimise ``stage``'s parameters for ``steps`` (with ``optimiser``, a fresh Adam over
    the stage's groups by default); returns the last step's loss. On a cancel or a non-finite
    loss restore the best state of this run (losses of one run share their weights and
    frames, so they compare) and raise Stop. ``first_step`` numbers the steps in history."""
    label = label or stage
    if optimiser is None:
        optimiser = torch.optim.Adam(stage_groups(params, stage, problem.config))
    problem.reporter.preview_source = lambda: preview(problem, params)
    best_total, best = math.inf, params.snapshot()
    total = math.inf
    leaves = [leaf for group in optimiser.param_groups for leaf in group["params"]]
    colour_geometry = problem.config.colour_moves_geometry(stage)
    # the colour term is read where it moves the geometry, where the stage fits the
    # appearance, and in the heading trials, whose choice compares totals
    colour = colour_geometry or fits_appearance(stage) or label == HEADING_STAGE
    for k in range(steps):
        weight = problem.config.weights.pyramid * pyramid_fade(k)
        problem.reporter.step_started()
        try:
            terms, iou = problem.step_loss(params, weight, leaves, colour, colour_geometry)
        except Cancelled:
            params.restore(best)
            raise Stop(STATUS_CANCELLED, "cancelled by the user", label, best_total,
                        params) from None
        if not math.isfinite(terms["total"]):
            params.restore(best)
            raise Stop(STATUS_DIVERGED, f"the loss became non-finite at step "
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


def preview(problem: FitProblem, params: SceneParams) -> FitPreview:
    """The current state, for display while the fit runs."""
    with torch.no_grad():
        betas = params.full_betas()
        rest, _ = problem.model.forward_rest(betas, problem.profile(params))
    return FitPreview(frame_idx=problem.data.frame_idx, transl=_copied(params.transl),
                      pose_aa=_copied(params.pose()), betas=_copied(betas),
                      rest_verts=_copied(rest))


def _copied(tensor: torch.Tensor) -> np.ndarray:
    """A NumPy copy on the CPU, apart from the parameters the optimiser goes on changing."""
    return tensor.detach().cpu().numpy().copy()


def debiased_targets(problem: FitProblem, params: SceneParams) -> torch.Tensor:
    """Soft targets with the renderer's edge profile, measured on the initial model."""
    with torch.no_grad():
        chunk = problem.data.every_frame()[:PROFILE_FRAMES]
        out = problem.render_chunk(params, chunk)
    profile = edge_profile(out.soft_mask, out.coverage)
    return soft_targets(problem.data.masks, profile, problem.config.target_edge_scale)
