"""The headless main job: fit the bundled sample clip and compare with its known truth.

  dolphinfit demo [--out DIR] [--quick]

The sample clip (a synthetic 1280×720 drone clip of a 2.45 m dolphin at 18 m, with a DJI SRT
sidecar and mask files) is rendered into the cache on first use. The demo fits it at 2.5 frames
per second, prints truth and estimate for volume, length and mass, and writes the outputs of
`dolphinfit fit` to DIR (default out/demo). --quick fits only its first second at the app's
"quick" quality: a check that an install works, not a measurement.
"""

import argparse
from dataclasses import replace
from pathlib import Path

from dolphinfit.app.commands.fit import report
from dolphinfit.app.progress import terminal_progress
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.outputs import check_fit_folder
from dolphinfit.core.fit.pipeline import CameraChoice, run_fit
from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.project.fit_settings import FitSettings, fit_config
from dolphinfit.core.synth.sample import SAMPLE_CONFIG, ensure_sample

DEMO_FPS = 2.5
QUICK_SECONDS = 1.0   # --quick fits this much of the clip


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``demo``."""
    parser.add_argument("--out", type=Path, default=Path("out/demo"), help="output folder")
    parser.add_argument("--quick", action="store_true",
                        help="fit the first second at quick quality (checks an install)")


def run(args: argparse.Namespace) -> int:
    """Make (or reuse) the sample, fit it, compare with the truth."""
    check_fit_folder(args.out, "--out ")
    print("sample clip: rendering on first use, then cached")
    files = ensure_sample()
    camera = CameraChoice(sensor_width_mm=SAMPLE_CONFIG.sensor_width_mm,
                          focal_mm=SAMPLE_CONFIG.focal_mm)
    config = (fit_config(FitSettings(start_s=0.0, end_s=QUICK_SECONDS, fps=DEMO_FPS,
                                     quality="quick")) if args.quick
              else replace(FitConfig(), fps=DEMO_FPS))
    fit_run = run_fit(files.video, files.srt, files.masks_dir, camera, config,
                      SAMPLE_CONFIG.launch_height_m, progress=terminal_progress())
    status = report(fit_run, args.out, camera)
    truth = read_json(files.truth_json, "the sample's truth")
    result = fit_run.result
    print("\n             truth     estimate   error")
    for name, key, value in (("volume m³", "volume_m3", result.volume_m3),
                             ("length m", "length_m", result.length_m),
                             ("mass kg", "mass_kg", result.mass_kg)):
        error = 100 * (value / truth[key] - 1)
        print(f"{name:11s} {truth[key]:9.4f}  {value:9.4f}  {error:+6.2f} %")
    return status
