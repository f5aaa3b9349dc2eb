"""Measure speed (and later accuracy) side by side in one run.

  dolphinfit bench render [--json] [--repeats N] [--quick]

render: forward+backward time of the differentiable renderer per frame at the paper's setting
(a full 720×480 frame) and for a batch of 256×256 ROI crops of 1920×1080 footage at 20 m,
against a forward-only OpenCV fill of the same triangles (ratio_vs_floor) and the dense
brute-force reference on the same scene at the largest size it fits in memory
(speedup_vs_dense), plus the peak memory of a 64-frame batch. --quick shrinks everything for
a smoke test; its figures are not the benchmark's.
"""

import argparse
import json

from core.bench.render_bench import RenderBench, bench_render, bench_to_json


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the benchmarks."""
    suites = parser.add_subparsers(dest="suite", required=True, metavar="SUITE")
    render = suites.add_parser("render", help="renderer speed against its floor and reference")
    render.add_argument("--json", action="store_true", help="one JSON object on stdout")
    render.add_argument("--repeats", type=int, default=5, help="timed repeats (median)")
    render.add_argument("--quick", action="store_true", help="tiny run for smoke tests")


def run(args: argparse.Namespace) -> int:
    """Run the chosen benchmark and print its figures."""
    result = bench_render(repeats=max(1, args.repeats), quick=args.quick)
    print(json.dumps(bench_to_json(result), indent=2) if args.json else format_render(result))
    return 0


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
        f"dense reference at {r.dense_size_px[0]}×{r.dense_size_px[1]}: {r.dense_ms:.0f} ms vs "
        f"sparse {r.sparse_ms_at_dense_size:.1f} ms → {r.speedup_vs_dense:.0f}× faster",
        f"peak memory, {r.memory_frames}-frame ROI batch forward+backward: "
        f"{r.peak_memory_mb:.0f} MB",
    ])
