"""``dolphinfit bench fit``: accuracy over a suite of synthetic clips, and speed on a long one.

Suite: 8 clips at 1920×1080 that differ in shape (random part scales, SD 0.05), length
(2.0–2.7 m), dive depth (0–1.5 m), altitude (15–25 m), water colour and clarity, sea state and
noise, with every effect the fit does not model switched on. Each clip is fitted three times,
side by side: with ROI crops and refraction, with ROI crops only (the default), and without
either (whole frames at 720 px, as the paper). Masks are the clips' true masks, so the figures measure the fit alone; altitude
comes from the DJI SRT sidecar. Clips are rendered once into the cache and reused.

Speed: a 10-second clip at 25 fps, 1920×1080, fitted with the defaults (5 frames per second of
video): wall time, seconds of fit per second of video, time by stage and peak memory.
"""

from dataclasses import asdict, dataclass, replace
import numpy as np

from core.bench.timing import run_with_peak_rss_mb
from core.fit.config import FitConfig
from core.fit.pipeline import CameraChoice, run_fit
from core.io.json_file import read_json
from core.synth.clip import make_clip
from core.synth.files import ClipFiles, clip_files
from core.synth.config import SynthConfig
from core.synth.sample import cache_dir

SUITE_NAME = "bench-suite-v1"
_BASE = SynthConfig(width_px=1920, height_px=1080, fps=10.0, duration_s=3.0, shape_sd=0.05)
SUITE: tuple[SynthConfig, ...] = (
    replace(_BASE, seed=101, length_m=2.0, altitude_m=15.0, dive_depth_m=0.0, sea_state=0.1,
            water_rgb=(0.05, 0.25, 0.30), clarity_per_m=(0.5, 0.15, 0.12), noise_sd=0.008),
    replace(_BASE, seed=102, length_m=2.2, altitude_m=18.0, dive_depth_m=0.5, sea_state=0.3,
            water_rgb=(0.06, 0.28, 0.26), clarity_per_m=(0.6, 0.2, 0.18)),
    replace(_BASE, seed=103, length_m=2.4, altitude_m=20.0, dive_depth_m=1.0, sea_state=0.5,
            water_rgb=(0.08, 0.30, 0.22), clarity_per_m=(0.7, 0.25, 0.3)),
    replace(_BASE, seed=104, length_m=2.5, altitude_m=22.0, dive_depth_m=1.5, sea_state=0.2,
            water_rgb=(0.04, 0.22, 0.34), clarity_per_m=(0.4, 0.1, 0.08)),
    replace(_BASE, seed=105, length_m=2.6, altitude_m=25.0, dive_depth_m=0.3, sea_state=0.7,
            water_rgb=(0.09, 0.27, 0.25), clarity_per_m=(0.9, 0.4, 0.35), noise_sd=0.012),
    replace(_BASE, seed=106, length_m=2.7, altitude_m=16.0, dive_depth_m=0.8, sea_state=0.4,
            water_rgb=(0.05, 0.24, 0.31)),
    replace(_BASE, seed=107, length_m=2.3, altitude_m=24.0, dive_depth_m=0.0, sea_state=0.9,
            noise_sd=0.015),
    replace(_BASE, seed=108, length_m=2.55, altitude_m=19.0, dive_depth_m=1.2, sea_state=0.6,
            water_rgb=(0.07, 0.29, 0.27), clarity_per_m=(0.55, 0.2, 0.2)),
)
VARIANTS: dict[str, dict] = {"roi_refraction": {"use_roi": True, "use_refraction": True},
                             "roi": {"use_roi": True, "use_refraction": False},
                             "no_roi": {"use_roi": False, "use_refraction": False}}
SUITE_FIT_FPS = 2.5
SPEED_CLIP = replace(_BASE, seed=201, fps=25.0, duration_s=10.0, dive_depth_m=0.6)


@dataclass(frozen=True)
class ClipScore:
    """One fit of one clip against its truth."""

    clip: str
    variant: str
    volume_error: float       # relative
    length_error: float
    mass_error: float
    mean_iou: float
    frames: int
    seconds: float


def _ensure(config: SynthConfig, name: str) -> ClipFiles:
    out = cache_dir() / SUITE_NAME / name
    files = clip_files(out, config)
    if files.truth_json.exists() and files.video.exists():
        return files
    return make_clip(config, out)


def _score(files: ClipFiles, config: SynthConfig, fit_config: FitConfig, name: str,
           variant: str) -> ClipScore:
    truth = read_json(files.truth_json, "the clip's truth")
    run = run_fit(files.video, files.srt, files.masks_dir,
                  CameraChoice(sensor_width_mm=config.sensor_width_mm, focal_mm=config.focal_mm),
                  fit_config, config.launch_height_m)
    result = run.result
    return ClipScore(clip=name, variant=variant,
                     volume_error=result.volume_m3 / truth["volume_m3"] - 1.0,
                     length_error=result.length_m / truth["length_m"] - 1.0,
                     mass_error=result.mass_kg / truth["mass_kg"] - 1.0,
                     mean_iou=float(result.iou.mean()), frames=len(result.frame_idx),
                     seconds=result.timings_s["total"])


def summarize(scores: list[ClipScore]) -> dict[str, dict[str, float]]:
    """Median and worst absolute errors per variant."""
    summary = {}
    for variant in dict.fromkeys(s.variant for s in scores):
        chosen = [s for s in scores if s.variant == variant]
        volume = np.abs([s.volume_error for s in chosen])
        length = np.abs([s.length_error for s in chosen])
        mass = np.abs([s.mass_error for s in chosen])
        summary[variant] = {"median_abs_volume_error": float(np.median(volume)),
                            "worst_abs_volume_error": float(volume.max()),
                            "median_abs_length_error": float(np.median(length)),
                            "worst_abs_length_error": float(length.max()),
                            "median_abs_mass_error": float(np.median(mass)),
                            "mean_seconds": float(np.mean([s.seconds for s in chosen]))}
    return summary


def bench_suite(num_clips: int = len(SUITE), variants: tuple[str, ...] = tuple(VARIANTS),
                progress=None, base: FitConfig | None = None) -> dict:
    """Fit every clip in every variant; per-clip scores and the summary.

    ``base``: the fit configuration the variants modify (default: the defaults at the
    suite's fitting rate).
    """
    base = base if base is not None else replace(FitConfig(), fps=SUITE_FIT_FPS)
    scores = []
    for index, config in enumerate(SUITE[:num_clips]):
        name = f"clip{index + 1}"
        files = _ensure(config, name)
        for variant in variants:
            scores.append(_score(files, config, replace(base, **VARIANTS[variant]), name,
                                 variant))
            if progress is not None:
                progress(scores[-1])
    return {"clips": [asdict(s) for s in scores], "summary": summarize(scores),
            "fit_fps": SUITE_FIT_FPS,
            "suite": [{"clip": f"clip{i + 1}", "length_m": c.length_m, "altitude_m": c.altitude_m,
                       "dive_depth_m": c.dive_depth_m, "sea_state": c.sea_state}
                      for i, c in enumerate(SUITE[:num_clips])]}


def bench_speed(clip: SynthConfig = SPEED_CLIP) -> dict:
    """Wall time and stages of a default fit of the speed clip, and the memory it added."""
    files = _ensure(clip, "speed")
    run, peak_mb = run_with_peak_rss_mb(lambda: run_fit(
        files.video, files.srt, files.masks_dir,
        CameraChoice(sensor_width_mm=clip.sensor_width_mm, focal_mm=clip.focal_mm),
        FitConfig(), clip.launch_height_m))
    timings = run.result.timings_s
    return {"video_s": clip.duration_s, "clip_fps": clip.fps, "fit_fps": FitConfig().fps,
            "frames_fitted": len(run.result.frame_idx), "wall_s": timings["total"],
            "fit_s_per_video_s": timings["total"] / clip.duration_s,
            "stages_s": {k: v for k, v in timings.items() if k != "total"},
            "peak_memory_mb": peak_mb, "mean_iou": float(run.result.iou.mean())}
