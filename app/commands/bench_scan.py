"""``dolphinfit bench scan``: the scan's picks against random frames on each suite split,
and its speed (core/bench/scan_bench.py).

  dolphinfit bench scan [--splits tuning,held-out,vtk] [--clips N] [--no-speed] [--json]
"""

import argparse
import sys

from dolphinfit.app.commands.bench_output import emit
from dolphinfit.app.commands.bench_splits import load_renderers
from dolphinfit.core.bench.scan_bench import AIM_S_PER_MINUTE, BEST, bench_scan
from dolphinfit.core.bench.suites import SPLITS, scenarios
from dolphinfit.core.limits import count, one_of

CLIP_WIDTH = 21


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Which splits, how many clips of each, and whether to time the speed clip."""
    parser.add_argument("--splits", default=",".join(SPLITS),
                        help=f"comma-separated, of {', '.join(SPLITS)} (default all, "
                             "reported apart)")
    parser.add_argument("--clips", type=int, default=None, metavar="N",
                        help="the first N clips of each split (default all)")
    parser.add_argument("--no-speed", action="store_true",
                        help="leave out the scan of the 10-s speed clip")
    parser.add_argument("--json", action="store_true", help="one JSON object on stdout")


def _print_clip(clip: dict) -> None:
    print(f"{clip['split']:9s} {clip['clip']:{CLIP_WIDTH}s} {_row(clip)}", file=sys.stderr,
          flush=True)


def _row(clip: dict) -> str:
    return (f"picked {100 * clip['picked_abs_error']:5.1f} %  random "
            f"{100 * clip['random_abs_error']:5.1f} %  | mean of {BEST}: picked "
            f"{100 * abs(clip['picked_mean_error']):5.1f} %  random "
            f"{100 * clip['random_abs_mean_error']:5.1f} %  ({clip['animals']} animals, "
            f"{clip['seconds']:.0f} s); scanned as a short clip ({clip['short_samples']} "
            f"samples): target {'found' if clip['short_target_found'] else 'MISSED'}")


def format_scan(figures: dict) -> str:
    """Per clip and per split: |volume error| of the picked and of random frames."""
    lines = [f"{'split':9s} {'clip':{CLIP_WIDTH}s} mean |elliptical volume error| of "
             f"{BEST} frames (true masks)"]
    for split, part in figures["splits"].items():
        lines += [f"{split:9s} {c['clip']:{CLIP_WIDTH}s} {_row(c)}" for c in part["clips"]]
        s = part["summary"]
        lines.append(f"{split:9s} {'mean':{CLIP_WIDTH}s} picked {100 * s['picked_abs_error']:5.1f}"
                     f" %  random {100 * s['random_abs_error']:5.1f} %  | mean of {BEST}: "
                     f"picked {100 * s['picked_abs_mean_error']:5.1f} %  random "
                     f"{100 * s['random_abs_mean_error']:5.1f} %  (picks better on "
                     f"{s['picks_better']} of {s['target_found']} clips; target found on "
                     f"{s['target_found']} of {s['clips']}, scanned as short clips on "
                     f"{s['short_target_found']})")
    if "speed" in figures:
        lines.append(speed_line(figures["speed"]))
    return "\n".join(lines)


def speed_line(speed: dict) -> str:
    """The speed clip's scan (core.bench.scan_bench.bench_speed) in one line, with its aim;
    also `bench app`'s."""
    return (f"the scan: {speed['video_s']:.0f} s of 1080p in {speed['seconds']:.1f} s, "
            f"{speed['seconds_per_video_minute']:.0f} s per minute of video (aim ≤ "
            f"{AIM_S_PER_MINUTE:.0f})")


def run(args: argparse.Namespace) -> int:
    """Run the scan bench and print its table."""
    names = tuple(args.splits.split(","))
    for name in names:
        one_of(name, SPLITS, "--splits")
    load_renderers(names)
    most = None if args.clips is None else count(args.clips, 1, "--clips")
    figures = bench_scan({name: scenarios(split=name)[:most] for name in names},
                         speed=not args.no_speed, progress=_print_clip)
    return emit(args, figures, format_scan)
