"""``dolphinfit bench batch``: throughput of ``dolphinfit batch`` in clips per hour on a
LocalCluster of 1 worker and of 2 workers, side by side in one run on the same short
synthetic clips (masks and altitude CSV from the clips' truth).

Each worker count runs the whole batch from scratch into its own folder; torch threads per
worker are the cores shared out (1 worker: all of them), as ``dolphinfit batch`` sets them,
so the figures compare one fit using every core with fits side by side.
"""

import json
import tempfile
import time
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from dolphinfit.core.batch.cluster import batch_client, local_plan
from dolphinfit.core.batch.manifest import read_manifest
from dolphinfit.core.batch.record import STATUS_COMPLETE
from dolphinfit.core.batch.runner import run_batch
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.project.fit_settings import FitSettings, fit_config
from dolphinfit.core.synth.clip import make_clip
from dolphinfit.core.synth.config import Effects, SynthConfig

# A short clip: 640×360 at 15 m (a 2.3 m animal is about 70 px long), 1.5 s at 8 fps, with
# the effects the fit does not model switched off (throughput, not accuracy, is measured).
BENCH_CLIP = SynthConfig(width_px=640, height_px=360, fps=8.0, duration_s=1.5,
                         altitude_m=15.0, length_m=2.3, speed_m_s=0.6, dive_depth_m=0.0,
                         effects=Effects(profile_warp=False, scattering=False, ripples=False,
                                         glints=False, compression=False))
BENCH_SETTINGS = FitSettings(fps=2.0, quality="quick")  # 3 frames, half the default steps
# A smoke test's fit: one step per stage
TINY_CONFIG = FitConfig(heading_trial_steps=1, steps_global=1, steps_body=1, steps_shape=1)
# A tiny task: 320×180 at 12 m, a 2.3 m animal about 45 px long; 4 frames, 2 of them fitted
# with one step per stage (about 0.4 s of work)
TINY_CLIP = SynthConfig(seed=41, width_px=320, height_px=180, fps=4.0, duration_s=1.0,
                        altitude_m=12.0, length_m=2.3, speed_m_s=0.5, dive_depth_m=0.0,
                        heading_deg=15.0, effects=Effects(profile_warp=False, scattering=False,
                                                          ripples=False, glints=False,
                                                          compression=False))
TINY_CLIP_CONFIG = replace(TINY_CONFIG, fps=2.0)
MANIFEST_HEADER = "clip,animal,altitude,masks,camera,sensor_width_mm,focal_mm,config"
MC_DRAWS = 200


def write_synthetic_batch(folder: Path, clips: Sequence[SynthConfig], config: FitConfig,
                          with_masks: bool = True, animals: int = 1) -> Path:
    """Render ``clips`` into ``folder/clipN/``, write ``config`` as ``folder/fit_config.json``
    and ``folder/manifest.csv`` (one animal per clip, its true masks unless ``with_masks`` is
    False: the tracker's automatic seed; with ``animals`` > 1, each clip's animal listed under
    the IDs 1…``animals``: that many tasks of equal work); the manifest's path."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "fit_config.json").write_text(json.dumps(config.to_json()))
    rows = [MANIFEST_HEADER]
    for index, clip in enumerate(clips):
        files = make_clip(clip, folder / f"clip{index}")
        masks = files.masks_dir.relative_to(folder).as_posix() if with_masks else ""
        rows += [f"{files.video.relative_to(folder).as_posix()},{animal},"
                 f"{files.altitude_csv.relative_to(folder).as_posix()},{masks},,"
                 f"{clip.sensor_width_mm},{clip.focal_mm},fit_config.json"
                 for animal in range(1, animals + 1)]
    manifest = folder / "manifest.csv"
    manifest.write_text("\n".join(rows) + "\n")
    return manifest


def bench_batch(num_clips: int = 4, worker_counts: Sequence[int] = (1, 2),
                quick: bool = False) -> dict:
    """Wall time and clips per hour of the same batch per worker count; ``quick``: tiny
    fits (a smoke test, not the benchmark's figures)."""
    clips = [replace(BENCH_CLIP, seed=300 + i, heading_deg=40.0 * i) for i in range(num_clips)]
    config = TINY_CONFIG if quick else fit_config(BENCH_SETTINGS)
    runs = []
    with tempfile.TemporaryDirectory(prefix="dolphinfit-bench-batch-") as tmp:
        manifest = write_synthetic_batch(Path(tmp), clips, config)
        tasks = read_manifest(manifest, MC_DRAWS)
        for workers in worker_counts:
            plan = local_plan(workers)
            with batch_client(plan=plan) as client:
                client.wait_for_workers(workers)
                start = time.perf_counter()
                records = run_batch(client, tasks, Path(tmp) / f"out_{workers}")
                wall_s = time.perf_counter() - start
            runs.append({"workers": workers, "torch_threads": plan.torch_threads,
                         "wall_s": wall_s, "clips_per_hour": 3600.0 * len(tasks) / wall_s,
                         "complete": sum(r.status == STATUS_COMPLETE for r in records),
                         "task_s": [round(r.seconds, 2) for r in records]})
    return {"clips": num_clips, "clip": {"width_px": BENCH_CLIP.width_px,
                                         "height_px": BENCH_CLIP.height_px,
                                         "duration_s": BENCH_CLIP.duration_s},
            "fit": {"fps": config.fps, "steps": config.total_steps,
                    "quality": "tiny" if quick else BENCH_SETTINGS.quality},
            "runs": runs,
            "speedup": runs[-1]["clips_per_hour"] / runs[0]["clips_per_hour"]}
