"""``dolphinfit bench e2e``: what a user waits for, from a clip to a result with its intervals.

The speed clip (``fit_bench.SPEED_CLIP``: 10 s at 25 fps, 1920×1080, DJI SRT altitudes) and the
same scene at 3840×2160 go through the chain ``dolphinfit fit`` runs when it is given no
masks: the scan of the fit's window that finds the animal (the automatic seed), the masks of
the frames the fit uses, the preparation of its crops, the fit's stages, and the Monte Carlo
of its 95 % intervals. Each stage's seconds come from the chain's own progress reports
(``StageClock``); beside them the chain's peak memory and its errors against the clip's
truth. Clips are rendered once into the cache (the 4K clip takes several minutes).

Each chain runs in a fresh child process (``chain_in_child``: this module's code, a checkout's
``dolphinfit``), so that none starts with the caches, the loaded networks or the memory of the
one before it. Run in the bench's own process after the 1080p chain, the 4K chain took 55 s
where a fresh process took 59–61 s. With a ``baseline`` checkout (an earlier dolphinfit, e.g.
``git worktree add ../before v0.1``), that checkout's chain runs frame size by frame size beside
this one's, so that before and after are measured in one run on one machine.
"""

import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import torch

from dolphinfit.core.bench.fit_bench import SPEED_CACHE, SPEED_CLIP
from dolphinfit.core.bench.scenario import synth_camera
from dolphinfit.core.bench.suites import FRAME_SIZES
from dolphinfit.core.bench.timing import run_with_peak_rss_mb
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.interval import run_interval
from dolphinfit.core.fit.pipeline import run_fit
from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.limits import one_of
from dolphinfit.core.measure.annotation import ALTITUDE_SOURCE_OF_KIND
from dolphinfit.core.measure.uncertainty import ErrorModel
from dolphinfit.core.progress import Progress
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.sample import cache_dir, ensure_clip

E2E_CACHE = "bench-e2e-v1"
INTERVAL_STAGE = "intervals"
# the aims on two cores, seconds from the clip to the result with its intervals
AIM_S = {"1080p": 30.0, "4k": 60.0}
# the root of this dolphinfit: the folder holding its core/, app/ and ui/ packages
PACKAGE_ROOT = Path(__file__).resolve().parents[2]


class StageClock:
    """A progress callback that times a chain's stages: each stage lasts from its first
    report to the first report of the next one; what comes before the first report is the
    "open" stage. A stage's first report comes after its first unit of work, so that unit
    counts to the stage before: "open" holds the scan's first sample (the whole frame looked
    at in tiles), "scan" the tracker's first look at the animal it was given."""

    def __init__(self) -> None:
        self.start = time.perf_counter()
        self.marks: list[tuple[str, float]] = [("open", self.start)]

    def __call__(self, report: Progress) -> None:
        if report.stage != self.marks[-1][0]:
            self.marks.append((report.stage, time.perf_counter()))

    def mark(self, stage: str) -> None:
        """A stage that reports no progress of its own begins now."""
        self.marks.append((stage, time.perf_counter()))

    def seconds(self) -> dict[str, float]:
        """Seconds by stage until now, a stage entered twice summed."""
        ends = [*(at for _, at in self.marks[1:]), time.perf_counter()]
        stages: dict[str, float] = {}
        for (stage, began), ended in zip(self.marks, ends, strict=True):
            stages[stage] = stages.get(stage, 0.0) + ended - began
        return stages


def clip_of(frame_size: str) -> SynthConfig:
    """The speed clip's scene at ``frame_size`` (a key of ``suites.FRAME_SIZES``)."""
    width, height = FRAME_SIZES[frame_size]
    return replace(SPEED_CLIP, width_px=width, height_px=height)


def _clip_dir(frame_size: str):
    """The 1080p clip is ``bench fit --speed``'s own; the others are cached apart."""
    if frame_size == "1080p":
        return cache_dir() / SPEED_CACHE / "speed"
    return cache_dir() / E2E_CACHE / frame_size


def bench_chain(frame_size: str, device: str | None = None) -> dict:
    """One run of the chain, with the default fit, on the speed clip at ``frame_size``:
    seconds by stage and in all, peak memory, frames, errors of volume and length, and
    whether the interval holds the true volume. ``device``: where the fit and the edge
    network run (core.device; None: the engine's default, the CPU, as an engine from before
    devices has it)."""
    on_device = {} if device is None else {"device": device}
    clip = clip_of(frame_size)
    files = ensure_clip(clip, _clip_dir(frame_size))
    truth = read_json(files.truth_json, "the clip's truth")
    errors = ErrorModel.default(ALTITUDE_SOURCE_OF_KIND["srt"], False)

    def chain():
        clock = StageClock()
        run = run_fit(files.video, files.srt, None, synth_camera(clip), FitConfig(),
                      clip.launch_height_m, progress=clock, **on_device)
        clock.mark(INTERVAL_STAGE)
        interval = run_interval(run, errors)
        return run, interval, clock.seconds()

    (run, interval, stages), peak_mb = run_with_peak_rss_mb(chain)
    result, volume = run.result, interval.volume_m3
    total = sum(stages.values())
    return {"frame_size": frame_size, "device": device or "cpu",
            "width_px": clip.width_px, "height_px": clip.height_px,
            "video_s": clip.duration_s, "frames_fitted": len(result.frame_idx),
            "total_s": total, "aim_s": AIM_S.get(frame_size), "stages_s": stages,
            "peak_memory_mb": peak_mb, "masks": run.masks.source,
            "volume_error": result.volume_m3 / truth["volume_m3"] - 1.0,
            "length_error": result.length_m / truth["length_m"] - 1.0,
            "interval_holds_volume": bool(volume.low <= truth["volume_m3"] <= volume.high)}


def chain_in_child(checkout: Path, frame_size: str, device: str | None = None) -> dict:
    """``bench_chain`` at ``frame_size`` (on ``device``) with the engine of the dolphinfit in
    ``checkout`` (the root of a clone, or of this installed package), in a fresh child process
    that imports that checkout's package first; RuntimeError with the child's error output
    when it fails."""
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "dolphinfit").symlink_to(Path(checkout).resolve(),
                                                 target_is_directory=True)
        code = ("import json, runpy, sys\n"
                "from dolphinfit.core.runtime import configure_threads\n"
                "configure_threads(int(sys.argv[3]))\n"
                "chain = runpy.run_path(sys.argv[1])['bench_chain']\n"
                "device = sys.argv[4] or None\n"
                "print(json.dumps(chain(sys.argv[2], device=device)))\n")
        done = subprocess.run(
            [sys.executable, "-c", code, __file__, frame_size, str(torch.get_num_threads()),
             device or ""],
            capture_output=True, text=True, env={**os.environ, "PYTHONPATH": folder})
    if done.returncode != 0:
        raise RuntimeError(f"the chain of {checkout} exited {done.returncode}: "
                           f"{done.stderr.strip()[-800:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def checkout_label(checkout: Path) -> str:
    """The commit a checkout is at (``git describe``), or its folder's name where git cannot
    say: what a kept run names its baseline by, not a path of one machine."""
    done = subprocess.run(["git", "-C", str(checkout), "describe", "--always", "--dirty"],
                          capture_output=True, text=True)
    return done.stdout.strip() if done.returncode == 0 else Path(checkout).resolve().name


def bench_e2e(frame_sizes: Sequence[str] = tuple(FRAME_SIZES), baseline: Path | None = None,
              device: str | None = None) -> dict:
    """The chain at each of ``frame_sizes`` on ``device``, in one run; with ``baseline`` (a
    checkout of an earlier dolphinfit) that one's chain beside each (module doc)."""
    for frame_size in frame_sizes:
        one_of(frame_size, tuple(FRAME_SIZES), "frame size")
    if device is not None:   # the CPU as None: what an engine from before devices runs on
        from dolphinfit.core.device import resolve_device
        device = None if resolve_device(device).type == "cpu" else device
    figures: dict = {"clip_fps": SPEED_CLIP.fps, "fit_fps": FitConfig().fps, "runs": []}
    if baseline is not None:
        figures["baseline"], figures["baseline_runs"] = checkout_label(baseline), []
    for frame_size in frame_sizes:
        if baseline is not None:
            figures["baseline_runs"].append(chain_in_child(baseline, frame_size, device))
        figures["runs"].append(chain_in_child(PACKAGE_ROOT, frame_size, device))
    return figures
