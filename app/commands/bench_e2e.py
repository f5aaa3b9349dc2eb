"""``dolphinfit bench e2e``: from the clip to the result with its intervals, stage by stage
(core/bench/e2e_bench.py).

  dolphinfit bench e2e [--frame-sizes 1080p,4k] [--baseline CHECKOUT] [--device D] [--json]
"""

import argparse
from pathlib import Path

from dolphinfit.app.commands.bench_output import emit
from dolphinfit.app.commands.device_option import add_device_argument, chosen_device
from dolphinfit.core.bench.e2e_bench import bench_e2e
from dolphinfit.core.bench.suites import FRAME_SIZES
from dolphinfit.core.errors import InputError
from dolphinfit.core.limits import one_of


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Which frame sizes."""
    parser.add_argument("--frame-sizes", default=",".join(FRAME_SIZES),
                        help=f"comma-separated, of {', '.join(FRAME_SIZES)} (default both)")
    parser.add_argument("--baseline", type=Path, default=None, metavar="CHECKOUT",
                        help="a checkout of an earlier dolphinfit (git worktree add); its chain "
                             "runs beside this one's in the same run")
    add_device_argument(parser, "where the fit and the edge network run (the baseline's too)")
    parser.add_argument("--json", action="store_true", help="one JSON object on stdout")


def format_e2e(figures: dict) -> str:
    """One block per frame size: the total against its aim, the stages, memory and errors;
    the baseline's first where there is one."""
    lines = []
    runs = [("", run) for run in figures["runs"]]
    if "baseline_runs" in figures:
        lines.append(f"baseline: {figures['baseline']}")
        runs = [pair for both in zip((("baseline ", run) for run in figures["baseline_runs"]),
                                     runs, strict=True) for pair in both]
    for name, run in runs:
        aim = "" if run["aim_s"] is None else f" (aim ≤ {run['aim_s']:.0f} s)"
        stages = ", ".join(f"{stage} {seconds:.1f}" for stage, seconds in
                           run["stages_s"].items())
        lines += [f"{name}{run['frame_size']}: {run['video_s']:.0f} s of {figures['clip_fps']:.0f} fps "
                  f"video, {run['frames_fitted']} frames fitted: {run['total_s']:.1f} s from "
                  f"clip to result{aim}",
                  f"  stages (s): {stages}",
                  f"  peak memory {run['peak_memory_mb']:.0f} MB; volume "
                  f"{100 * run['volume_error']:+.2f} %, length {100 * run['length_error']:+.2f}"
                  f" %; the 95 % interval {'holds' if run['interval_holds_volume'] else 'misses'}"
                  f" the true volume"]
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Run the chain at each frame size and print its table."""
    frame_sizes = tuple(args.frame_sizes.split(","))
    for frame_size in frame_sizes:
        one_of(frame_size, tuple(FRAME_SIZES), "--frame-sizes")
    if args.baseline is not None and not (args.baseline / "core" / "fit" / "pipeline.py").is_file():
        raise InputError(f"--baseline {args.baseline}: not a checkout of dolphinfit (no "
                         f"core/fit/pipeline.py there)")
    chosen_device(args)   # cuda where torch sees none: refused before any work
    return emit(args, bench_e2e(frame_sizes, args.baseline, args.device), format_e2e)
