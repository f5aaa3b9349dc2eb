"""``dolphinfit bench fit``: accuracy over the widened synthetic suite, and speed on a long clip.

Suite: the scenarios of ``core.bench.suites`` (1920×1080 clips of light-grey and dark animals
over green, blue, sandy and murky water, pairs, splash, glitter and sharp turns, with every
effect the fit does not model on). Beside each error stands the clip's hidden-height floor
(``core.bench.hidden_heights``): what a top view must miss with the fit's assumed heights and
sections. Each clip is fitted side by side in the chosen variants:
by default with the clip's true masks (the fit alone) and with the product's own masks (the
default mask back-end from a click on the target, as a user would start it), at 2.5 frames
per second of video. Altitude comes from the DJI SRT sidecar. Clips are rendered once into
the cache and reused.

Speed: a 10-second clip at 25 fps, 1920×1080, fitted with the defaults (5 frames per second of
video) and, side by side in the same run, exhaustively (``EXHAUSTIVE``): wall time, seconds of
fit per second of video, time by stage, peak memory and the errors against the clip's truth.
"""

from collections.abc import Sequence
from dataclasses import asdict, dataclass, replace

import numpy as np

from dolphinfit.core.bench.hidden_heights import TruthSections, hidden_height_floor, truth_sections
from dolphinfit.core.bench.mask_bench import AUTO, CLICK, click_seed
from dolphinfit.core.bench.scenario import Scenario, ensure_scenario, synth_camera
from dolphinfit.core.bench.timing import run_with_peak_rss_mb
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig, LossWeights
from dolphinfit.core.fit.interval import run_interval
from dolphinfit.core.fit.pipeline import run_fit
from dolphinfit.core.fit.result import STATUS_COMPLETE
from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.measure.uncertainty import ErrorModel
from dolphinfit.core.segment.backends import DEFAULT_BACKEND, NETWORK_COLOUR_EDGES
from dolphinfit.core.segment.segmenter import AutoSeed, Seed
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import ClipFiles
from dolphinfit.core.synth.sample import cache_dir, ensure_clip

# The fit before its speed work: every face in the soft mask, every frame in every step, native
# resolution throughout. Measured beside the defaults by both the suite and the speed run.
EXHAUSTIVE = {"soft_primitives": "faces", "heading_max_frames": 0, "shape_max_frames": 0,
              "coarse_factor": 1}
# the depth prior off: depth and overall size trade freely, as before it
FREE_DEPTH = {"weights": LossWeights(depth=0.0)}
# the soft targets' edge scale set before the depth prior
EDGE_BEFORE_DEPTH_PRIOR = {"target_edge_scale": 0.78}


@dataclass(frozen=True)
class Variant:
    """One way of fitting a suite clip."""

    backend: str | None   # the mask back-end; None for the clip's true masks
    options: dict         # fit options over the defaults
    seed: str = CLICK     # how the back-end starts: CLICK on the target, or the AUTO seed


VARIANTS: dict[str, Variant] = {
    "true_masks": Variant(None, {}),
    "true_masks_exhaustive": Variant(None, EXHAUSTIVE),
    "product_masks": Variant(DEFAULT_BACKEND, {}),
    # the product's masks with no click: the automatic seed finds the animal, as `dolphinfit
    # fit` does without --masks
    "product_masks_auto_seed": Variant(DEFAULT_BACKEND, {}, seed=AUTO),
    "product_masks_exhaustive": Variant(DEFAULT_BACKEND, EXHAUSTIVE),
    # the network's masks with the outline placed by colour (the default before the edge net)
    "product_masks_colour_edges": Variant(NETWORK_COLOUR_EDGES, {}),
    "true_masks_refraction": Variant(None, {"use_refraction": True}),
    "true_masks_no_roi": Variant(None, {"use_roi": False, "use_refraction": True}),
    "true_masks_colour_all_stages": Variant(None, {"colour_geometry": "all_stages"}),
    "true_masks_colour_pose_stages": Variant(None, {"colour_geometry": "pose_stages"}),
    "true_masks_paper_pose_prior": Variant(None, {"weights": LossWeights(pose=2.0)}),
    # the body free to bend up or down for good (no pitch-bend prior), as before it
    "true_masks_free_bend": Variant(None, {"weights": LossWeights(pitch_bend=0.0)}),
    "product_masks_auto_seed_free_bend": Variant(DEFAULT_BACKEND,
                                                 {"weights": LossWeights(pitch_bend=0.0)},
                                                 seed=AUTO),
    # the shape stage on every frame, pitched and rolled ones included (none set aside)
    "true_masks_all_shape_frames": Variant(None, {"shape_iou_margin": 1.0}),
    # the axes prior (each part's axes scale together) off, and ten times the default
    "true_masks_no_axes_prior": Variant(None, {"weights": LossWeights(scale_axes=0.0)}),
    "true_masks_strong_axes_prior": Variant(None, {"weights": LossWeights(scale_axes=1.0)}),
    # the parts' scales alone, without the profile field along the body
    "true_masks_no_profile_field": Variant(None, {"profile_field": False}),
    # the hidden heights from the template's own height/width ratios, not the HW table's
    "true_masks_template_heights": Variant(None, {"hw_table": None}),
    # the fit before both: the parts' scales alone and the template's heights
    "true_masks_before_field_and_table": Variant(None, {"profile_field": False,
                                                         "hw_table": None}),
    "true_masks_free_depth": Variant(None, FREE_DEPTH),
    "true_masks_edge_078": Variant(None, EDGE_BEFORE_DEPTH_PRIOR),
    "true_masks_before_depth_prior": Variant(None, {**FREE_DEPTH, **EDGE_BEFORE_DEPTH_PRIOR}),
    "product_masks_free_depth": Variant(DEFAULT_BACKEND, FREE_DEPTH),
    "product_masks_edge_078": Variant(DEFAULT_BACKEND, EDGE_BEFORE_DEPTH_PRIOR),
}
DEFAULT_VARIANTS = ("true_masks", "product_masks")
CLAIM_LIMIT = 0.10     # a complete fit's volume should lie within this of the truth
SUITE_FIT_FPS = 2.5
SUITE_ERRORS = ErrorModel(altitude_sd_fraction=0.0, focal_sd_fraction=0.0,
                          digitisation_sd_px=0.0, hw_sd_scale=1.0)
SPEED_CACHE = "bench-speed-v1"
_SPEED_BASE = SynthConfig(width_px=1920, height_px=1080, fps=10.0, duration_s=3.0,
                          shape_sd=0.05)
SPEED_CLIP = replace(_SPEED_BASE, seed=201, fps=25.0, duration_s=10.0, dive_depth_m=0.6)


@dataclass(frozen=True)
class ClipScore:
    """One fit of one clip against its truth."""

    clip: str
    variant: str
    volume_error: float       # relative
    length_error: float
    mass_error: float
    mean_iou: float
    min_iou: float            # the worst fitted frame's IoU
    frames: int
    seconds: float
    frame_iou: tuple[float, ...]   # per fitted frame, in time order
    # the volume error a top view must make on this animal with this fit's assumed heights
    # and sections (core.bench.hidden_heights): the floor under volume_error
    hidden_height_floor: float = float("nan")
    error: str = ""                # why there is no fit (its errors are then NaN)
    # the fit's 95 % volume interval (SUITE_ERRORS) as errors against the truth
    volume_low_error: float = float("nan")
    volume_high_error: float = float("nan")
    status: str = ""               # the fit's: complete or unreliable (core.fit.reliability)
    reasons: tuple[str, ...] = ()


def _score(files: ClipFiles, config: SynthConfig, fit_config: FitConfig, name: str,
           variant: str, sections: TruthSections) -> ClipScore:
    truth = read_json(files.truth_json, "the clip's truth")
    backend = VARIANTS[variant].backend
    camera = synth_camera(config)
    try:
        if backend is None:
            run = run_fit(files.video, files.srt, files.masks_dir, camera, fit_config,
                          config.launch_height_m)
        else:
            run = run_fit(files.video, files.srt, None, camera, fit_config,
                          config.launch_height_m, seed=_seed(files, VARIANTS[variant].seed),
                          backend=backend)
    except InputError as exc:  # e.g. masks that leave no frame to fit: a failed clip
        nan = float("nan")
        return ClipScore(clip=name, variant=variant, volume_error=nan, length_error=nan,
                         mass_error=nan, mean_iou=nan, min_iou=nan, frames=0, seconds=nan,
                         frame_iou=(), error=str(exc))
    result = run.result
    volume = run_interval(run, SUITE_ERRORS).volume_m3
    return ClipScore(clip=name, variant=variant,
                     volume_low_error=float(volume.low) / truth["volume_m3"] - 1.0,
                     volume_high_error=float(volume.high) / truth["volume_m3"] - 1.0,
                     hidden_height_floor=hidden_height_floor(sections, fit_config),
                     volume_error=result.volume_m3 / truth["volume_m3"] - 1.0,
                     length_error=result.length_m / truth["length_m"] - 1.0,
                     mass_error=result.mass_kg / truth["mass_kg"] - 1.0,
                     mean_iou=float(result.iou.mean()), min_iou=float(result.iou.min()),
                     frames=len(result.frame_idx), seconds=result.timings_s["total"],
                     frame_iou=tuple(float(v) for v in result.iou), status=result.status,
                     reasons=result.reasons)


def _seed(files: ClipFiles, kind: str) -> Seed:
    """A click on the target, or the automatic seed from frame 0 (it scans on by itself)."""
    return click_seed(files) if kind == CLICK else AutoSeed(frame_idx=0)


def summarize(scores: list[ClipScore]) -> dict[str, dict[str, float]]:
    """Median and worst absolute errors per variant, over the clips that were fitted; how
    many were not, how many say they are unreliable, and how many complete ones are more than
    ``CLAIM_LIMIT`` off in volume."""
    summary = {}
    for variant in dict.fromkeys(s.variant for s in scores):
        failed = sum(1 for s in scores if s.variant == variant and s.error)
        chosen = [s for s in scores if s.variant == variant and not s.error]
        if not chosen:
            summary[variant] = {"failed": failed}
            continue
        volume = np.abs([s.volume_error for s in chosen])
        length = np.abs([s.length_error for s in chosen])
        mass = np.abs([s.mass_error for s in chosen])
        floor = np.abs([s.hidden_height_floor for s in chosen])
        held = [s.volume_low_error <= 0.0 <= s.volume_high_error for s in chosen]
        half_width = [(s.volume_high_error - s.volume_low_error) / 2 for s in chosen]
        summary[variant] = {"median_abs_volume_error": float(np.median(volume)),
                            "worst_abs_volume_error": float(volume.max()),
                            "median_abs_length_error": float(np.median(length)),
                            "worst_abs_length_error": float(length.max()),
                            "median_abs_mass_error": float(np.median(mass)),
                            "median_abs_hidden_height_floor": float(np.median(floor)),
                            "worst_abs_hidden_height_floor": float(floor.max()),
                            "volume_interval_coverage": float(np.mean(held)),
                            "median_volume_interval_half_width": float(np.median(half_width)),
                            "mean_iou": float(np.mean([s.mean_iou for s in chosen])),
                            "unreliable": sum(s.status != STATUS_COMPLETE for s in chosen),
                            # what must never happen: a fit off by more than CLAIM_LIMIT
                            # that calls itself complete
                            "complete_but_off": sum(s.status == STATUS_COMPLETE
                                                    and abs(s.volume_error) > CLAIM_LIMIT
                                                    for s in chosen),
                            "mean_seconds": float(np.mean([s.seconds for s in chosen])),
                            "failed": failed}
    return summary


def bench_suite(chosen: Sequence[Scenario], variants: tuple[str, ...] = DEFAULT_VARIANTS,
                progress=None, base: FitConfig | None = None) -> dict:
    """Fit every clip of the ``chosen`` scenarios in every variant; per-clip scores and the
    summary.

    ``base``: the fit configuration the variants modify (default: the defaults at the
    suite's fitting rate).
    """
    unknown = [v for v in variants if v not in VARIANTS]
    if unknown:
        raise InputError(f"bench fit variants {', '.join(unknown)}: unknown; choose from "
                         f"{', '.join(VARIANTS)}")
    base = base if base is not None else replace(FitConfig(), fps=SUITE_FIT_FPS)
    scores = []
    for scenario in chosen:
        files = ensure_scenario(scenario)
        sections = truth_sections(scenario.config)
        for variant in variants:
            scores.append(_score(files, scenario.config,
                                 replace(base, **VARIANTS[variant].options), scenario.name,
                                 variant, sections))
            if progress is not None:
                progress(scores[-1])
    return {"clips": [asdict(s) for s in scores], "summary": summarize(scores),
            "fit_fps": base.fps, "suite": sorted({sc.suite for sc in chosen}),
            "scenarios": [{"clip": sc.name, "shows": sc.shows,
                           "length_m": sc.config.length_m, "altitude_m": sc.config.altitude_m,
                           "hw_table": sc.config.hw_table,
                           "section_exponent": sc.config.section_exponent}
                          for sc in chosen]}


def bench_speed(clip: SynthConfig = SPEED_CLIP, exhaustive: bool = True) -> dict:
    """A default fit of the speed clip and, with ``exhaustive``, an exhaustive one of the
    same data: wall time, stages, the memory each added and their errors."""
    files = ensure_clip(clip, cache_dir() / SPEED_CACHE / "speed")
    truth = read_json(files.truth_json, "the clip's truth")
    configs = {"default": FitConfig()}
    if exhaustive:
        configs["exhaustive"] = FitConfig(**EXHAUSTIVE)
    runs = {}
    for name, config in configs.items():
        run, peak_mb = run_with_peak_rss_mb(lambda c=config: run_fit(
            files.video, files.srt, files.masks_dir,
            synth_camera(clip), c, clip.launch_height_m))
        result = run.result
        timings = result.timings_s
        runs[name] = {"frames_fitted": len(result.frame_idx), "wall_s": timings["total"],
                      "fit_s_per_video_s": timings["total"] / clip.duration_s,
                      "stages_s": {k: v for k, v in timings.items() if k != "total"},
                      "peak_memory_mb": peak_mb, "mean_iou": float(result.iou.mean()),
                      "volume_error": result.volume_m3 / truth["volume_m3"] - 1.0,
                      "length_error": result.length_m / truth["length_m"] - 1.0}
    figures = {"video_s": clip.duration_s, "clip_fps": clip.fps, "fit_fps": FitConfig().fps,
               "runs": runs}
    if exhaustive:
        figures["speedup"] = runs["exhaustive"]["wall_s"] / runs["default"]["wall_s"]
    return figures
