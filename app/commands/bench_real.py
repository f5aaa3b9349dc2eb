"""``dolphinfit bench real``: the product against people on real drone images (the parts are
described in core/bench/real_bench.py).

  dolphinfit bench real [--data DIR] [--parts P,…] [--seeds click,auto] [--backend B]
                        [--outlines N] [--overlays DIR] [--json]
"""

import argparse
import math
import sys
from pathlib import Path

from dolphinfit.app.commands.bench_output import emit
from dolphinfit.core.bench.real_bench import PARTS, SEEDS, bench_real
from dolphinfit.core.limits import count, one_of
from dolphinfit.core.segment.backends import ALWAYS_AVAILABLE, DEFAULT_BACKEND, make_segmenter


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The data folder, the seeds and back-end of the masks, how many outlines."""
    parser.add_argument("--data", type=Path, default=None, metavar="DIR",
                        help="the real data sets (default: the clone's tests/data/real)")
    parser.add_argument("--parts", default=",".join(PARTS),
                        help=f"comma-separated, of {', '.join(PARTS)} (default all)")
    parser.add_argument("--seeds", default=",".join(SEEDS),
                        help=f"comma-separated, of {', '.join(SEEDS)} (default all)")
    parser.add_argument("--backend", choices=ALWAYS_AVAILABLE, default=DEFAULT_BACKEND,
                        help=f"mask back-end (default {DEFAULT_BACKEND})")
    parser.add_argument("--outlines", type=int, default=None, metavar="N",
                        help="score only the first N whale outlines (default all)")
    parser.add_argument("--overlays", type=Path, default=None, metavar="DIR",
                        help="write a picture of our mask, midline and widths over each "
                             "image there")
    parser.add_argument("--json", action="store_true", help="one JSON object on stdout")


def run(args: argparse.Namespace) -> int:
    """Score the product against people and print the table."""
    parts, seeds = tuple(args.parts.split(",")), tuple(args.seeds.split(","))
    for part in parts:
        one_of(part, PARTS, "--parts")
    for kind in seeds:
        one_of(kind, SEEDS, "--seeds")
    limit = None if args.outlines is None else count(args.outlines, 1, "--outlines")
    make_segmenter(args.backend)  # its weights missing: refused before any work
    figures = bench_real(args.data, parts, seeds, args.backend, limit,
                         progress=lambda line: print(line, file=sys.stderr, flush=True),
                         overlays=args.overlays)
    return emit(args, figures, format_real)


def _px(offset: float) -> str:
    return "—" if math.isnan(offset) else f"{offset:+.0f}"


def _pct(share: float) -> str:
    return f"{100 * share:+.1f} %"


def format_real(figures: dict) -> str:
    """One table per part, the people's spread beside our error."""
    lines: list[str] = []
    if "medidor_replay" in figures:
        lines += _replay_lines(figures["medidor_replay"])
    if "minke" in figures:
        lines += _minke_lines(figures["minke"])
    if "right_whale" in figures:
        lines += _right_whale_lines(figures["right_whale"])
    if "outlines" in figures:
        lines += _outline_lines(figures["outlines"])
    if "minke_fit" in figures:
        lines += _fit_lines(figures["minke_fit"])
    return "\n".join(lines).rstrip("\n")


def _replay_lines(replay: dict) -> list[str]:
    return ["MedidoR's test clicks replayed (right whale, 2.7K): body length "
             f"{replay['length_px']:.2f} px against its sheet's {replay['sheet_length_px']:.2f};"
             f" largest difference of length and 9 widths {replay['max_abs_difference_px']:.2g}"
             f" px with MedidoR's geometry, {replay['default_max_abs_difference_px']:.2f} px "
             "with ours (spline, perpendicular widths)", ""]


def _minke_lines(minke: dict) -> list[str]:
    spread = minke["human_spread"]
    lengths = " / ".join(f"{h['length_m']:.3f}" for h in minke["humans"])
    lines = [f"Minke whale (28.4 m, 3.2 mm/px), two people: length {lengths} m (spread "
              f"{spread['length_m']:.3f} m, {100 * spread['length_share']:.1f} %); widths at "
              f"{len(spread['stations_pct'])} stations differ by {100 * spread['median_width_share']:.1f}"
              f" % median, {100 * spread['worst_width_share']:.1f} % worst",
              "seed   length m  vs people  widths: median |error|  worst   within spread  s"]
    for kind, s in minke["seeds"].items():
        if s["error"]:
            lines.append(f"{kind:6s} no mask: {s['error']}")
            continue
        lines.append(f"{kind:6s} {s['length_m']:8.3f}  {_pct(s['length_error_share']):>9s}  "
                     f"{100 * s['median_width_error_share']:14.1f} %  "
                     f"{100 * s['worst_width_error_share']:6.1f} %  "
                     f"{s['widths_within_spread']:6d} of {len(s['width_error_m'])}  "
                     f"{s['seconds']:5.1f}")
    return lines + [""]


def _right_whale_lines(whale: dict) -> list[str]:
    lines = [f"Right whale with calf (MedidoR's test clicks, not an expert's; length "
             f"{whale['sheet_length_px']:.1f} px)",
              "seed   length px  vs clicks  outline − each clicked edge point, px, 10 … 90 % "
             "(first/second click of the pair; + outside)"]
    for kind, s in whale["seeds"].items():
        if s["error"]:
            lines.append(f"{kind:6s} no mask: {s['error']}")
            continue
        offsets = " ".join(f"{_px(first)}/{_px(second)}" for second, first in s["offset_px"])
        lines.append(f"{kind:6s} {s['length_px']:9.1f}  "
                     f"{_pct(s['length_px'] / whale['sheet_length_px'] - 1):>9s}"
                     f"  {offsets}  (median |offset| {s['median_abs_offset_px']:.1f} px)")
    return lines + [""]


def _outline_lines(out: dict) -> list[str]:
    ends = out["ends"]
    lines = [f"Whale outlines with hand points ({out['outlines']} outlines, rostrum to "
             f"peduncle, no flippers or flukes; {len(out['left_out'])} left out): our "
             f"midline (its head end given) ends beyond the person's rostrum point by "
             f"{ends['rostrum']['median_offset_px']:+.1f} px (median; worst "
             f"{ends['rostrum']['worst_offset_px']:+.0f}) and their peduncle point by "
             f"{ends['peduncle']['median_offset_px']:+.1f} px (median |·| "
             f"{ends['peduncle']['median_abs_offset_px']:.1f}, worst "
             f"{ends['peduncle']['worst_offset_px']:+.0f}), along the body",
              "pair            ours − person          outline − person       ours − outline",
              "                median  worst (px, %)  median  worst          median  worst"]
    for pair, p in out["pairs"].items():
        cells = "  ".join(f"{v['median_px']:5.1f} {100 * v['median_share']:4.1f}%  "
                          f"{v['worst_px']:5.0f} {100 * v['worst_share']:3.0f}%"
                          for v in p.values())
        lines.append(f"{pair:15s} {cells}")
    return lines


def _fit_lines(fit: dict) -> list[str]:
    interval = fit["interval"]

    def shown(key: str, fmt: str) -> str:
        return (f"{fit[key]:{fmt}} ({interval[key]['low']:{fmt}}–"
                f"{interval[key]['high']:{fmt}})")

    lines = ["", f"Minke whale, the 3D fit from a click ({fit['status']}, mean IoU "
             f"{fit['mean_iou']:.3f}, {fit['seconds']:.0f} s; 95 % intervals with the altitude "
             f"from the {fit['altitude_source']} and the outline ±{fit['outline_sd_px']:.2g} px)"
             f": length {shown('length_m', '.3f')} m, volume {shown('volume_m3', '.3f')} m³, "
             f"mass {shown('mass_kg', '.0f')} kg",
             "person                  length m  fit vs person  in the interval  widths: "
             "median |fit − person|"]
    for person in fit["people"]:
        lines.append(f"{person['source']:22s} {person['length_m']:9.3f}  "
                     f"{_pct(person['length_error_share']):>13s}  "
                     f"{'yes' if person['length_in_interval'] else 'no':>15s}  "
                     f"{100 * person['median_width_error_share']:8.1f} %")
    return lines
