"""Measure speed and accuracy side by side in one run.

  dolphinfit bench render [--json] [--repeats N] [--quick]
  dolphinfit bench fit (--suite [--splits P,…] [--clips N] [--shapes S] [--frame-size F]
                       [--variants V,…] | --speed) [--json]
  dolphinfit bench masks [--splits P,…] [--clips N | --only NAME,…] [--shapes S]
                         [--frame-size F] [--backends B,…] [--seeds S,…]
                         [--sam2-checkpoint PATH] [--stride K] [--json]
  dolphinfit bench masks --sweep [--backends B,…] [--json]
  dolphinfit bench app [--parts startup,click,scan] [--repeats N] [--bundle PROGRAM] [--json]
  dolphinfit bench batch [--clips N] [--quick] [--json]
  dolphinfit bench batch --faults [--tasks N] [--json]
  dolphinfit bench real [--data DIR] [--seeds S,…] [--backend B] [--outlines N] [--json]
  dolphinfit bench scan [--splits tuning,held-out,vtk] [--clips N] [--no-speed] [--json]
  dolphinfit bench e2e [--frame-sizes 1080p,4k] [--json]

render: forward+backward time of the differentiable renderer per frame at the paper's setting
(a full 720×480 frame) and for a batch of 256×256 ROI crops of 1920×1080 footage at 20 m,
against a forward-only OpenCV fill of the same triangles (ratio_vs_floor) and the dense
brute-force reference on the same scene at the largest size it fits in memory
(speedup_vs_dense), plus the peak memory of a 64-frame batch. Forward and backward are timed
within the same repeats. The soft mask is the default "contour" one, and for the ROI batch
also DIB-R's "faces" one side by side; the dense comparison uses "faces" on both sides.
--quick shrinks everything for a smoke test; its figures are not the benchmark's.

fit --suite: the widened synthetic suite (12 1920×1080 clips: light-grey and dark animals over
green, blue, sandy and murky water, pairs, splash, glitter, sharp turns; every unmodelled
effect on), each fitted in the chosen variants side by side (default: the true masks and the
product's own masks from a click on the target): relative errors of volume, length and mass
per clip, their median and worst, and the fit's IoU per frame. --shapes varied (default)
gives the animals heights drawn from the default HW table and cross-sections from lean to
full (the animals someone else built); --shapes template keeps the template's heights and
elliptical sections (the suite before); --frame-size 4k renders the same scenes at 3840×2160
(default 1080p). Beside the tuning split, by default (--splits), the held-out split's eight
clips nothing was tuned on (core/bench/held_out.py: foreign bodies, other waters, foam wash,
5K delivered at 720p, H.264) and the VTK split's eight, drawn by another renderer
(core/bench/vtk_split.py), each reported apart. fit --speed: a 10 s, 25 fps,
1920×1080 clip fitted with the defaults and exhaustively (every face in the soft mask, every
frame in every step, native resolution: the fit before its speed work), side by side: wall
time, seconds of fit per second of video, time by stage, peak memory, errors against the
truth. Clips are rendered once into the cache.

masks: each mask back-end from the same click on the target, on the frames a suite fit uses
(every 4th): IoU against the true masks, IoU around the flukes and around the rostrum (the
parts that decide the length), the outline offset (how far the outline lies outside or
inside the true one, in pixels: what volume follows) and seconds per frame, in all and apart
(the seed, once per clip, then each frame tracked after it); the same from
the automatic seed and from a box around the target (--seeds, default click,auto,box; the
click always), on each split apart (--splits: tuning, held-out and the VTK split by default).
The default back-ends are those that need nothing beyond dolphinfit (network,
network-as-drawn, network-colour-edges, colour); SAM-2 joins them with --backends
network,colour,sam2 --sam2-checkpoint PATH where its package is installed. --sweep runs
instead one family of short clips varied one thing at a time (blur σ 0.3–2 px, contrast 5–60
grey levels, dark over dark and light over light, sensor noise, H.264 CRF 18–35, filmed at 2×
and 4× and delivered at 720p, animals 8–60 px wide: core/bench/sweep.py): per point, each
back-end's outline offset, IoU and the error of the elliptical volume its masks give against
the same measured on the true masks.

app: how long the desktop app takes from the command to the sample project's first frame on
screen (``dolphinfit gui --sample --quit-when-shown``), beside the floor of an empty PySide6
window in a fresh Python; min, median and max over --repeats runs. Needs a display (run it
under xvfb-run on a server). Then (part "click", core/bench/click_bench.py) how long a user
waits after a click on the animal of a 10-s 1080p clip: to that frame's mask, and to the
masks of every frame a default fit uses; and (part "scan") the scan's time per minute of
video on that clip (as `bench scan`'s speed).

batch: throughput of `dolphinfit batch` (clips per hour) on a LocalCluster of 1 worker and of
2 workers, on the same 4 short synthetic clips (640×360, 1.5 s, 3 frames fitted, quick
quality); --quick fits one step per stage (a smoke test). batch --faults: the fault drill
(core/bench/batch_faults.py): --tasks tiny tasks (default 120) on 2 workers, one worker process
killed once a quarter are done, the batch process with its scheduler once three fifths are,
the same batch rerun to the end; then every task must be complete or failed with a reason,
the summary hold a row per task and no task have completed twice (exit 1 otherwise).

real: the product against people on real drone images and measurements (core/bench/
real_bench.py): MedidoR's clicks replayed, our masks' length and widths against two people's
on a minke whale and against the clicks on a right whale with foam and a calf, our midline and
widths on 639 real whale outlines with hand points.

scan: whether the scan's best frames of each animal measure better than random frames (the
elliptical volume from the true masks on the frames it picks, core/bench/scan_bench.py), on
both splits apart, and its seconds per minute of 1080p video.

e2e: what a user waits for (core/bench/e2e_bench.py): the 10-s speed clip at 1080p and the
same scene at 4K taken from the clip to the result with its 95 % intervals as `dolphinfit fit`
does without masks (the scan for the animal, the masks of the fitted frames, the crops, the
fit's stages, the intervals' Monte Carlo), stage by stage, with peak memory and errors
against the truth.
"""

import argparse
import os
import statistics
import sys
from pathlib import Path

import numpy as np

from dolphinfit.app.commands import bench_e2e, bench_faults, bench_real, bench_scan
from dolphinfit.app.commands.bench_output import emit
from dolphinfit.app.commands.bench_splits import load_renderers
from dolphinfit.app.commands.masks import add_sam2_argument, sam2_checkpoint
from dolphinfit.core.bench.batch_bench import bench_batch
from dolphinfit.core.bench.click_bench import bench_click
from dolphinfit.core.bench.scan_bench import bench_speed as bench_scan_speed
from dolphinfit.core.bench.fit_bench import DEFAULT_VARIANTS, VARIANTS, bench_speed, bench_suite
from dolphinfit.core.bench.mask_bench import DEFAULT_STRIDE, SEED_KINDS, bench_masks
from dolphinfit.core.bench.render_bench import RenderBench, bench_render, bench_to_json
from dolphinfit.core.bench.sweep import bench_sweep
from dolphinfit.core.bench.scenario import Scenario, ensure_scenario
from dolphinfit.core.bench.suites import (
    DEFAULT_FRAME_SIZE, DEFAULT_SHAPES, FRAME_SIZES, SHAPES, SPLITS, scenarios,
)
from dolphinfit.core.bench.timing import command_seconds
from dolphinfit.core.errors import InputError
from dolphinfit.core.limits import count, one_of
from dolphinfit.core.segment.backends import ALWAYS_AVAILABLE, BACKENDS, make_segmenter

CLIP_WIDTH = 21   # the longest clip name of the splits (slender_pair_touching)
# The floor of the app's start-up: Python, PySide6 and one empty window shown, then quit
APP_PARTS = ("startup", "click", "scan")
EMPTY_WINDOW = ("from PySide6.QtCore import QTimer\n"
                "from PySide6.QtWidgets import QApplication, QMainWindow\n"
                "app = QApplication([])\nwindow = QMainWindow()\nwindow.show()\n"
                "QTimer.singleShot(0, app.quit)\napp.exec()\n")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the benchmarks."""
    suites = parser.add_subparsers(dest="suite_name", required=True, metavar="SUITE")
    render = suites.add_parser("render", help="renderer speed against its floor and reference")
    render.add_argument("--json", action="store_true", help="one JSON object on stdout")
    render.add_argument("--repeats", type=int, default=5, help="timed repeats (median)")
    render.add_argument("--quick", action="store_true", help="tiny run for smoke tests")
    fit = suites.add_parser("fit", help="fit accuracy over a clip suite, or fit speed")
    which = fit.add_mutually_exclusive_group(required=True)
    which.add_argument("--suite", action="store_true", help="accuracy over the clip suite")
    which.add_argument("--speed", action="store_true", help="speed on a 10 s clip")
    _add_split_argument(fit)
    fit.add_argument("--clips", type=int, default=None,
                     help="each split's first N clips (default all)")
    fit.add_argument("--shapes", choices=SHAPES, default=DEFAULT_SHAPES,
                     help=f"the suite's animals (default {DEFAULT_SHAPES}; see above)")
    fit.add_argument("--frame-size", choices=tuple(FRAME_SIZES), default=DEFAULT_FRAME_SIZE,
                     help=f"the suite's frame size (default {DEFAULT_FRAME_SIZE})")
    fit.add_argument("--variants", default=",".join(DEFAULT_VARIANTS),
                     help=f"comma-separated, of {', '.join(VARIANTS)} "
                          f"(default {','.join(DEFAULT_VARIANTS)})")
    fit.add_argument("--json", action="store_true", help="one JSON object on stdout")
    masks = suites.add_parser("masks", help="mask back-ends against the truth on the suite")
    _add_split_argument(masks)
    masks.add_argument("--clips", type=int, default=None,
                       help="each split's first N clips (default all)")
    masks.add_argument("--only", default="",
                       help="comma-separated suite clip names to run instead (e.g. "
                            "grey_green,dark_sandy)")
    masks.add_argument("--shapes", choices=SHAPES, default=DEFAULT_SHAPES,
                       help=f"the suite's animals (default {DEFAULT_SHAPES})")
    masks.add_argument("--frame-size", choices=tuple(FRAME_SIZES), default=DEFAULT_FRAME_SIZE,
                       help=f"the suite's frame size (default {DEFAULT_FRAME_SIZE})")
    masks.add_argument("--backends", default=",".join(ALWAYS_AVAILABLE),
                       help=f"comma-separated, of {', '.join(BACKENDS)} "
                            f"(default {','.join(ALWAYS_AVAILABLE)})")
    add_sam2_argument(masks)
    masks.add_argument("--seeds", default=",".join(SEED_KINDS),
                       help=f"comma-separated, of {', '.join(SEED_KINDS)} (the click always)")
    masks.add_argument("--stride", type=int, default=DEFAULT_STRIDE,
                       help=f"score every K-th frame (default {DEFAULT_STRIDE})")
    masks.add_argument("--sweep", action="store_true",
                       help="instead of the splits: one family of short clips over blur, "
                            "contrast, noise, compression, delivered size and the animal's "
                            "width (core/bench/sweep.py), each back-end from a click")
    masks.add_argument("--json", action="store_true", help="one JSON object on stdout")
    app = suites.add_parser("app", help="desktop app start-up against an empty Qt window, "
                                        "and the wait from a click to masks")
    app.add_argument("--parts", default=",".join(APP_PARTS),
                     help=f"comma-separated, of {', '.join(APP_PARTS)} (default all)")
    app.add_argument("--repeats", type=int, default=5, help="timed start-ups of each command")
    app.add_argument("--bundle", type=Path, default=None, metavar="PROGRAM",
                     help="also time the desktop bundle's start-up (bundle/dolphinfit/"
                          "dolphinfit, from make bundle) and report its size")
    app.add_argument("--json", action="store_true", help="one JSON object on stdout")
    batch = suites.add_parser("batch", help="batch throughput on 1 and 2 Dask workers")
    batch.add_argument("--clips", type=int, default=4, help="synthetic clips (default 4)")
    batch.add_argument("--quick", action="store_true", help="tiny fits for smoke tests")
    batch.add_argument("--json", action="store_true", help="one JSON object on stdout")
    bench_faults.add_arguments(batch)
    bench_real.add_arguments(suites.add_parser(
        "real", help="masks, midlines and widths against people on real drone images"))
    bench_scan.add_arguments(suites.add_parser(
        "scan", help="the scan's picked frames against random ones, and its speed"))
    bench_e2e.add_arguments(suites.add_parser(
        "e2e", help="from the clip to the result with intervals, stage by stage"))


def run(args: argparse.Namespace) -> int:
    """Run the chosen benchmark and print its figures."""
    if args.suite_name == "real":
        return bench_real.run(args)
    if args.suite_name == "scan":
        return bench_scan.run(args)
    if args.suite_name == "e2e":
        return bench_e2e.run(args)
    if args.suite_name == "app":
        parts = tuple(args.parts.split(","))
        for part in parts:
            one_of(part, APP_PARTS, "--parts")
        figures = {}
        if "startup" in parts:
            figures["startup"] = bench_app(max(1, args.repeats), args.bundle)
        if "click" in parts:
            figures["click"] = bench_click()
        if "scan" in parts:
            from dolphinfit.core.scan.scanner import Scanner
            figures["scan"] = bench_scan_speed(Scanner())
        return emit(args, figures, format_app)
    if args.suite_name == "batch":
        if args.faults:
            return bench_faults.run(args)
        if args.tasks is not None:
            raise InputError("--tasks goes with --faults")
        figures = bench_batch(max(1, args.clips), quick=args.quick)
        return emit(args, figures, format_batch)
    if args.suite_name in ("masks", "fit"):
        load_renderers(_split_names(args))
    if args.suite_name == "masks":
        backends = tuple(args.backends.split(","))
        checkpoint = sam2_checkpoint(args, backends)
        for backend in backends:  # an unknown or unavailable one is refused before any work
            make_segmenter(backend, checkpoint=checkpoint)
        if args.sweep:
            return emit(args, bench_sweep(backends, progress=_print_sweep_row), format_sweep)
        seeds = tuple(args.seeds.split(","))
        for kind in seeds:
            one_of(kind, SEED_KINDS, "--seeds")
        figures = {"splits": {}}
        for split, chosen in _chosen_clips(args).items():
            print(f"the {split} split", file=sys.stderr, flush=True)
            figures["splits"][split] = bench_masks(
                {sc.name: ensure_scenario(sc) for sc in chosen}, backends,
                count(args.stride, 1, "--stride"), seeds, progress=_print_mask_score,
                checkpoint=checkpoint)
        return emit(args, figures, _per_split(format_masks))
    if args.suite_name == "fit":
        if not args.suite:
            return emit(args, bench_speed(), format_speed)
        variants = tuple(args.variants.split(","))
        figures = {"splits": {}}
        for split, chosen in _chosen_clips(args).items():
            print(f"the {split} split", file=sys.stderr, flush=True)
            figures["splits"][split] = bench_suite(chosen, variants=variants,
                                                   progress=_print_score)
        return emit(args, figures, _per_split(format_suite))
    result = bench_render(repeats=max(1, args.repeats), quick=args.quick)
    return emit(args, bench_to_json(result), lambda _: format_render(result))


def _add_split_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--splits", default=",".join(SPLITS),
                        help=f"comma-separated, of {', '.join(SPLITS)} (default all, reported "
                             "apart): the tuning split, the held-out one and the one VTK draws "
                             "(neither ever tuned on)")


def _split_names(args: argparse.Namespace) -> tuple[str, ...]:
    """The --splits asked for, each checked."""
    names = tuple(dict.fromkeys(args.splits.split(",")))
    for name in names:
        one_of(name, SPLITS, "--splits")
    return names


def _chosen_clips(args: argparse.Namespace) -> dict[str, tuple[Scenario, ...]]:
    """Per split asked for, its first --clips scenarios, or those --only names in the order
    given (each from the split that has it; InputError for a name none has)."""
    splits = {name: scenarios(args.shapes, args.frame_size, name)
              for name in _split_names(args)}
    if not getattr(args, "only", ""):
        most = count(args.clips, 1, "--clips") if args.clips is not None else None
        return {name: chosen[:most] for name, chosen in splits.items()}
    names = args.only.split(",")
    known = {sc.name for chosen in splits.values() for sc in chosen}
    for name in names:
        one_of(name, tuple(known), "--only")
    picked = {split: tuple(by_name[name] for name in names if name in by_name)
              for split, by_name in ((split, {sc.name: sc for sc in chosen})
                                     for split, chosen in splits.items())}
    return {split: chosen for split, chosen in picked.items() if chosen}


def _per_split(format_split):
    """A formatter of ``{"splits": {name: figures}}`` that formats each split's figures
    under its name."""
    return lambda figures: "\n\n".join(f"== the {split} split ==\n{format_split(part)}"
                                        for split, part in figures["splits"].items())


def bench_app(repeats: int, bundle: Path | None = None) -> dict:
    """Start-up seconds of the app on the sample and of an empty window, and their ratio;
    with ``bundle`` (the desktop bundle's program, `make bundle`) its start-up on the sample
    too and its folder's size."""
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        raise InputError("bench app needs a display: run it under xvfb-run -a")
    from dolphinfit.core.project.sample import ensure_sample_project
    ensure_sample_project()  # rendered once, outside the timing
    commands = {
        "app_to_first_frame_s": [sys.executable, "-m", "dolphinfit.app.cli", "gui", "--sample",
                                 "--quit-when-shown"],
        "empty_window_s": [sys.executable, "-c", EMPTY_WINDOW],
    }
    figures: dict = {"repeats": repeats}
    if bundle is not None:
        if not bundle.is_file():
            raise InputError(f"--bundle {bundle}: no such program (make bundle builds "
                             f"bundle/dolphinfit/dolphinfit)")
        commands["bundle_to_first_frame_s"] = [str(bundle), "gui", "--sample",
                                               "--quit-when-shown"]
        figures["bundle_size_mb"] = sum(f.stat().st_size for f in bundle.parent.rglob("*")
                                        if f.is_file() and not f.is_symlink()) / 1e6
    for name, argv in commands.items():
        times = command_seconds(argv, repeats)
        figures[name] = {"min": min(times), "median": statistics.median(times),
                         "max": max(times)}
    figures["ratio_vs_empty_window"] = (figures["app_to_first_frame_s"]["median"]
                                        / figures["empty_window_s"]["median"])
    return figures


def format_app(figures: dict) -> str:
    """The start-up figures, one line each, then the wait from a click."""
    lines = []
    if "startup" in figures:
        startup = figures["startup"]
        lines += [f"{name:22s} min {t['min']:.2f} s  median {t['median']:.2f} s  "
                  f"max {t['max']:.2f} s" for name, t in startup.items() if isinstance(t, dict)]
        lines.append(f"app / empty window: {startup['ratio_vs_empty_window']:.1f}× "
                     f"({startup['repeats']} runs each)")
        if "bundle_size_mb" in startup:
            lines.append(f"the desktop bundle: {startup['bundle_size_mb']:.0f} MB")
    if "click" in figures:
        click = figures["click"]
        aims = click["aims_s"]
        lines.append(
            f"a click on the animal ({click['width_px']}×{click['height_px']}, "
            f"{click['video_s']:.0f} s at {click['clip_fps']:.0f} fps, frame "
            f"{click['clicked_frame']}, {click['backend']}): its mask after "
            f"{click['first_mask_s']:.1f} s (aim ≤ {aims['first_mask_s']:.0f}), the fit's "
            f"{click['fit_frames']} frames after {click['fit_masks_s']:.1f} s (aim ≤ "
            f"{aims['fit_masks_s']:.0f}); IoU {click['mean_iou']:.3f} (worst "
            f"{click['worst_iou']:.3f})")
    if "scan" in figures:
        lines.append(bench_scan.speed_line(figures["scan"]))
    return "\n".join(lines)


def _print_score(score) -> None:
    print(f"{score.clip:{CLIP_WIDTH}s} {score.variant:14s} volume "
          f"{100 * score.volume_error:+6.2f} %  length {100 * score.length_error:+6.2f} %  "
          f"IoU {score.mean_iou:.3f}  {score.seconds:.0f} s", file=sys.stderr, flush=True)


def _print_mask_score(score) -> None:
    others = "".join(f"  {kind} IoU {s.mean_iou:.3f}" for kind, s in score.seeds.items())
    print(f"{score.clip:{CLIP_WIDTH}s} {score.backend:20s} IoU {score.mean_iou:.3f}  flukes "
          f"{score.flukes_iou:.3f}  rostrum {score.rostrum_iou:.3f}  outline "
          f"{score.outline_offset_px:+.2f} px  {score.seconds_per_frame:.2f} s/frame (seed "
          f"{score.seed_seconds:.2f} s, then {score.seconds_per_tracked_frame:.2f}){others} "
          f"{score.error}", file=sys.stderr, flush=True)


def format_masks(figures: dict) -> str:
    """Per-clip IoUs and outline offsets and the summary per back-end, from the click and from
    the other seeds (IoU, flukes, rostrum IoU of each)."""
    kinds = list(figures["clips"][0]["seeds"])
    lines = [f"{'clip':{CLIP_WIDTH}s} back-end              IoU    min    flukes rostrum "
             "outline px s/frame seed s then"
             + "".join(f"  {kind:>5s}: IoU  fl    ro" for kind in kinds)]
    for c in figures["clips"]:
        errors = [c["error"]] + [c["seeds"][kind]["error"] for kind in kinds]
        lines.append(f"{c['clip']:{CLIP_WIDTH}s} {c['backend']:20s}  {c['mean_iou']:.3f}  "
                     f"{c['min_iou']:.3f}  {c['flukes_iou']:.3f}  {c['rostrum_iou']:.3f}   "
                     f"{c['outline_offset_px']:+6.2f}     {c['seconds_per_frame']:.2f}   "
                     f"{c['seed_seconds']:5.2f}  {c['seconds_per_tracked_frame']:.2f}"
                     + "".join(f"        {_ious(c['seeds'][kind])}" for kind in kinds)
                     + "".join(f"  ({e})" for e in errors if e))
    lines.append("")
    for backend, s in figures["summary"].items():
        lines.append(f"{backend:20s} mean IoU {s['mean_iou']:.3f} (worst clip "
                     f"{s['worst_clip_iou']:.3f}), flukes {s['flukes_iou']:.3f}, rostrum "
                     f"{s['rostrum_iou']:.3f}, outline offset {s['mean_abs_outline_offset_px']:.2f} "
                     f"px (worst clip {s['worst_outline_offset_px']:.2f}), "
                     f"{s['seconds_per_frame']:.2f} s per frame (the seed "
                     f"{s['seed_seconds']:.2f} s, then {s['seconds_per_tracked_frame']:.2f} s "
                     f"per frame tracked)"
                     + "".join(f"; {kind}: {t['mean_iou']:.3f} (worst clip "
                               f"{t['worst_clip_iou']:.3f})" for kind, t in s["seeds"].items()))
    return "\n".join(lines)


def _sweep_row(row: dict) -> str:
    if not row["visible"]:
        return (f"{row['factor']:12s} {row['value']:26s} not visible (the generator's rule; "
                f"body contrast × {row['body_contrast']:.2f})")
    return (f"{row['factor']:12s} {row['value']:26s} {row['contrast_levels']:5.1f} "
            f"{row['width_px']:5.1f}" + "".join(
                f"   {s['outline_offset_px']:+6.2f} {s['mean_iou']:.3f} "
                f"{100 * s['volume_error']:+6.1f} %" for s in row["backends"].values())
            + "".join(f"  ({name}: {s['error']})" for name, s in row["backends"].items()
                      if s.get("error")))


def _print_sweep_row(row: dict) -> None:
    print(_sweep_row(row), file=sys.stderr, flush=True)


def format_sweep(figures: dict) -> str:
    """The sweep's table: each point's contrast and width, then per back-end its outline
    offset, IoU and the elliptical volume error of its masks against the true masks."""
    visible = [row for row in figures["points"] if row["visible"]]
    backends = list(visible[0]["backends"])
    lines = [f"{'factor':12s} {'value':26s} grey  width" + "".join(
        f"   {name[:22]:>22s}" for name in backends),
        f"{'':12s} {'':26s} lvls  px   " + "   outline  IoU  volume" * len(backends)]
    lines += [_sweep_row(row) for row in figures["points"]]
    for backend in backends:
        offsets = np.abs([row["backends"][backend]["outline_offset_px"] for row in visible])
        lines.append(f"{backend}: mean |outline offset| {offsets.mean():.2f} px, worst "
                     f"{offsets.max():.2f} px over the {len(offsets)} points where the animal "
                     f"is visible")
    return "\n".join(lines)


def _ious(score: dict) -> str:
    return f"{score['mean_iou']:.3f} {score['flukes_iou']:.3f} {score['rostrum_iou']:.3f}"


def format_suite(figures: dict) -> str:
    """Per-clip errors and the summary per variant."""
    lines = [f"{'clip':{CLIP_WIDTH}s} variant         volume    (floor)    (95 % interval)     "
             "length    mass      IoU   min IoU frames  s"]
    for c in figures["clips"]:
        lines.append(f"{c['clip']:{CLIP_WIDTH}s} {c['variant']:14s} "
                     f"{100 * c['volume_error']:+6.2f} %  "
                     f"({100 * c['hidden_height_floor']:+6.2f} %)  "
                     f"({100 * c['volume_low_error']:+5.1f} … "
                     f"{100 * c['volume_high_error']:+5.1f} %)  "
                     f"{100 * c['length_error']:+6.2f} %  {100 * c['mass_error']:+6.2f} %  "
                     f"{c['mean_iou']:.3f}  {c['min_iou']:.3f}  {c['frames']:6d}  "
                     f"{c['seconds']:.0f}  {c.get('status', '')}"
                     + (f"  ({c['error']})" if c["error"] else ""))
    lines.append("")
    for variant, s in figures["summary"].items():
        if "median_abs_volume_error" not in s:
            lines.append(f"{variant:14s} no clip fitted ({s['failed']} failed)")
            continue
        lines.append(f"{variant:14s} ({s['failed']} failed) |volume| median "
                     f"{100 * s['median_abs_volume_error']:.2f} %, "
                     f"worst {100 * s['worst_abs_volume_error']:.2f} % (hidden-height floor "
                     f"{100 * s['median_abs_hidden_height_floor']:.2f} %, "
                     f"{100 * s['worst_abs_hidden_height_floor']:.2f} %); |length| median "
                     f"{100 * s['median_abs_length_error']:.2f} %, worst "
                     f"{100 * s['worst_abs_length_error']:.2f} %; |mass| median "
                     f"{100 * s['median_abs_mass_error']:.2f} %; mean IoU {s['mean_iou']:.3f}; "
                     f"the fit's 95 % volume interval (outline, heights) holds the truth on "
                     f"{100 * s['volume_interval_coverage']:.0f} % of clips, half-width median "
                     f"{100 * s['median_volume_interval_half_width']:.1f} %; "
                     f"{s.get('unreliable', 0)} say they are unreliable, "
                     f"{s.get('complete_but_off', 0)} complete ones are more than 10 % off")
    return "\n".join(lines)


def format_speed(figures: dict) -> str:
    """Wall time, rate, stages and errors of each speed run, and the ratio."""
    lines = [f"{figures['video_s']:.0f} s of {figures['clip_fps']:.0f} fps video, fitted at "
             f"{figures['fit_fps']:g} frames per second of video"]
    for name, run in figures["runs"].items():
        stages = ", ".join(f"{k} {v:.0f} s" for k, v in run["stages_s"].items())
        lines.append(f"{name:10s} {run['frames_fitted']} frames: {run['wall_s']:.0f} s "
                     f"({run['fit_s_per_video_s']:.1f} s per second of video); {stages}; peak "
                     f"memory {run['peak_memory_mb']:.0f} MB; volume "
                     f"{100 * run['volume_error']:+.2f} %, length "
                     f"{100 * run['length_error']:+.2f} %, mean IoU {run['mean_iou']:.3f}")
    if "speedup" in figures:
        lines.append(f"exhaustive / default: {figures['speedup']:.2f}×")
    return "\n".join(lines)


def format_batch(figures: dict) -> str:
    """Clips per hour per worker count, and the ratio."""
    lines = [f"{figures['clips']} clips of {figures['clip']['duration_s']:g} s at "
             f"{figures['clip']['width_px']}×{figures['clip']['height_px']}, "
             f"{figures['fit']['steps']} fit steps at {figures['fit']['fps']:g} frames/s"]
    lines += [f"{r['workers']} worker(s) × {r['torch_threads']} torch thread(s): "
              f"{r['wall_s']:.0f} s, {r['clips_per_hour']:.0f} clips/hour "
              f"({r['complete']} complete)" for r in figures["runs"]]
    lines.append(f"2 workers / 1 worker: {figures['speedup']:.2f}×")
    return "\n".join(lines)


def format_render(r: RenderBench) -> str:
    """The renderer figures as a small report."""
    return "\n".join([
        f"renderer, {r.faces} faces, {r.threads} torch thread(s), torch {r.torch_version}",
        f"paper setting, full 720×480 frame ({r.paper_covered_px} px covered):",
        f"  forward {r.paper_forward_ms:.1f} ms + backward {r.paper_backward_ms:.1f} ms "
        f"= {r.paper_ms:.1f} ms per frame",
        f"  OpenCV fill floor {r.paper_floor_ms:.2f} ms → ratio {r.ratio_vs_floor:.1f}×",
        "ROI crops 256×256 of 1920×1080 at 20 m:",
        f"  forward {r.roi_forward_ms:.1f} ms + backward {r.roi_backward_ms:.1f} ms "
        f"= {r.roi_ms:.1f} ms per frame",
        f"  OpenCV fill floor {r.roi_floor_ms:.2f} ms → ratio {r.roi_ratio_vs_floor:.1f}×",
        f"  with DIB-R's soft mask over faces: {r.roi_faces_ms:.1f} ms per frame → ratio "
        f"{r.roi_faces_ratio_vs_floor:.1f}×",
        f"dense reference at {r.dense_size_px[0]}×{r.dense_size_px[1]}: {r.dense_ms:.0f} ms vs "
        f"sparse {r.sparse_ms_at_dense_size:.1f} ms → {r.speedup_vs_dense:.0f}× faster",
        f"peak memory, {r.memory_frames}-frame ROI batch forward+backward: "
        f"{r.peak_memory_mb:.0f} MB",
    ])
