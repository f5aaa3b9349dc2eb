"""``dolphinfit bench scan``: does the scan pick the frames that measure well, and how long
does it take?

**Picks.** Each suite clip is scanned (every other frame: ``SAMPLE_FPS``); the target is the
animal whose sightings lie on the true mask most often. On every sampled frame where the
target shows, the fit-free elliptical volume is measured from the **true** mask (the
midline and widths "suggest edges" places, the default HW table), so that what is compared
is the choice of frame, not the mask. Reported per clip: the mean |volume error| of the
scan's best ``BEST`` frames, and of ``BEST`` frames drawn at random from the same samples
(the expectation: the mean over every sampled frame), and the same for the volume averaged
over the ``BEST`` frames (random: the mean over ``RANDOM_DRAWS`` seeded draws).

**Short clips.** Each clip is scanned again as a user's scan of a short clip would sample it
(the default ``ScanSettings``: a frame a second, so the suite's 3-s clips give 3 samples, a
4-s field clip 4): whether the target is found (an animal whose sightings lie on its true
mask), where every target shows plainly.

**Speed.** The 10-s 25-fps 1080p speed clip scanned with the default settings: seconds, and
seconds per minute of video.
"""

from collections.abc import Callable

import numpy as np

from dolphinfit.core.bench.scenario import Scenario, ensure_scenario, synth_camera
from dolphinfit.core.bench.fit_bench import SPEED_CACHE, SPEED_CLIP
from dolphinfit.core.io.frame_source import Clip
from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.io.masks import MaskTrack, read_masks
from dolphinfit.core.io.telemetry import Telemetry, load_telemetry
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.measure.annotation import pixel_measurements
from dolphinfit.core.measure.elliptical import TAIL_EXTRAPOLATED, elliptical_volume, fill_skipped
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET, load_hw_preset
from dolphinfit.core.measure.mask_midline import annotation_from_mask
from dolphinfit.core.scan.clip_scan import ClipScan, ClipTelemetry
from dolphinfit.core.scan.scanner import Scanner
from dolphinfit.core.scan.frame_scores import ScanSettings
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import ClipFiles
from dolphinfit.core.synth.sample import cache_dir, ensure_clip

SAMPLE_FPS = 5.0        # the suite's clips are 3 s at 10 fps: every other frame
BEST = 5
AIM_S_PER_MINUTE = 30.0  # the scan's seconds per minute of 1080p on two cores (issue 28)
RANDOM_DRAWS = 2000


def elliptical_error(mask: np.ndarray, altitude_m: float, focal_px: float,
                     truth_m3: float) -> float:
    """Relative error of the elliptical volume measured on ``mask`` (module doc); NaN where
    the mask gives no midline."""
    try:
        pixels = pixel_measurements(annotation_from_mask(mask))
    except ValueError:
        return float("nan")
    metres_per_px = altitude_m / focal_px
    widths, _ = fill_skipped(pixels.widths_px * metres_per_px, TAIL_EXTRAPOLATED)
    volume = elliptical_volume(np.array(pixels.length_px * metres_per_px), widths,
                               load_hw_preset(DEFAULT_PRESET).ratios, TAIL_EXTRAPOLATED)
    return float(volume) / truth_m3 - 1.0


def target_animal(scan: ClipScan, truth_masks: MaskTrack) -> int | None:
    """The animal whose sightings' centres lie on the true mask most often."""
    def hits(animal: int) -> int:
        return sum(bool(truth_masks.mask(s.frame_idx)[round(s.centre_y_px),
                                                      round(s.centre_x_px)])
                   for s in scan.of_animal(animal))
    ids = [animal for animal in scan.animal_ids() if hits(animal) > 0]
    return max(ids, key=hits) if ids else None


def scanned(files: ClipFiles, config: SynthConfig, scanner: Scanner,
            settings: ScanSettings) -> tuple[ClipScan, Clip, Telemetry, float]:
    """A synthetic clip scanned with its own camera and altitudes; the scan, the clip, its
    altitudes and its focal length in pixels."""
    clip = open_clip(files.video)
    telemetry = load_telemetry(clip, files.altitude_csv)
    focal_px = synth_camera(config).intrinsics(clip).focal_px
    with VideoReader(clip) as frames:
        scan = scanner.scan(frames, ClipTelemetry(focal_px, telemetry.altitude_m,
                                                  np.full(clip.num_frames, np.nan)), settings)
    return scan, clip, telemetry, focal_px


def score_clip(scenario: Scenario, scanner: Scanner) -> dict:
    """One clip's picks against random frames (module doc)."""
    files = ensure_scenario(scenario)
    scan, clip, telemetry, focal_px = scanned(files, scenario.config, scanner,
                                              ScanSettings(sample_fps=SAMPLE_FPS))
    truth_masks = read_masks(files.masks_dir, clip)
    truth_m3 = float(read_json(files.truth_json, "the truth")["volume_m3"])
    errors = {t: elliptical_error(truth_masks.mask(t), float(telemetry.altitude_m[t]), focal_px,
                                  truth_m3)
              for t in scan.sampled_frames if truth_masks.mask(t).any()}
    errors = {t: e for t, e in errors.items() if np.isfinite(e)}
    target = target_animal(scan, truth_masks)
    short, _, _, _ = scanned(files, scenario.config, scanner, ScanSettings())
    picks = [s.frame_idx for s in scan.best(target, BEST)] if target is not None else []
    picked = np.array([errors[t] for t in picks if t in errors])
    every = np.array(list(errors.values()))
    rng = np.random.default_rng(0)  # each draw: BEST different frames, as the picks are
    draws = np.array([rng.choice(len(every), min(BEST, len(every)), replace=False)
                      for _ in range(RANDOM_DRAWS)])
    return {"clip": scenario.name, "seconds": scan.seconds, "animals": len(scan.animal_ids()),
            "target_found": target is not None, "picks": picks,
            "short_samples": len(short.sampled_frames),
            "short_target_found": target_animal(short, truth_masks) is not None,
            "picked_abs_error": float(np.abs(picked).mean()) if picked.size else float("nan"),
            "random_abs_error": float(np.abs(every).mean()),
            "picked_mean_error": float(picked.mean()) if picked.size else float("nan"),
            "random_abs_mean_error": float(np.abs(every[draws].mean(axis=1)).mean())}


def bench_speed(scanner: Scanner) -> dict:
    """The speed clip scanned with the default settings (module doc)."""
    files = ensure_clip(SPEED_CLIP, cache_dir() / SPEED_CACHE / "speed")
    scan, clip, _, _ = scanned(files, SPEED_CLIP, scanner, ScanSettings())
    return {"seconds": scan.seconds, "video_s": clip.duration_s,
            "seconds_per_video_minute": scan.seconds * 60.0 / clip.duration_s,
            "samples": len(scan.sampled_frames), "animals": len(scan.animal_ids())}


def summarize(clips: list[dict]) -> dict:
    """Means over the clips, and on how many the picks beat random frames."""
    found = [c for c in clips if c["target_found"]]
    return {"clips": len(clips), "target_found": len(found),
            "short_target_found": sum(c["short_target_found"] for c in clips),
            "picked_abs_error": float(np.nanmean([c["picked_abs_error"] for c in found])),
            "random_abs_error": float(np.mean([c["random_abs_error"] for c in clips])),
            "picks_better": sum(c["picked_abs_error"] < c["random_abs_error"] for c in found),
            "picked_abs_mean_error": float(np.nanmean([abs(c["picked_mean_error"])
                                                       for c in found])),
            "random_abs_mean_error": float(np.mean([c["random_abs_mean_error"]
                                                    for c in clips]))}


def bench_scan(splits: dict[str, tuple[Scenario, ...]], speed: bool = True,
               progress: Callable[[dict], None] | None = None) -> dict:
    """Picks per clip and split, each split summarised apart, and the speed (module doc)."""
    scanner = Scanner()
    figures: dict = {"splits": {}}
    for split, chosen in splits.items():
        clips = []
        for scenario in chosen:
            clips.append(score_clip(scenario, scanner) | {"split": split})
            if progress is not None:
                progress(clips[-1])
        figures["splits"][split] = {"clips": clips, "summary": summarize(clips)}
    if speed:
        figures["speed"] = bench_speed(scanner)
    return figures
