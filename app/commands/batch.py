"""Fit and measure many clips and animals as Dask tasks, resumably, into one summary table.

  dolphinfit batch MANIFEST.csv [--out DIR] [--scheduler ADDRESS | --workers N]
                   [--retry-failed] [--mc N] [--device auto|cpu|cuda]
  dolphinfit batch PROJECT.dolphinfit [same options]

A manifest is a CSV with one row per clip and animal (columns in core/batch/manifest.py and
the manual's batches guide: clip, animal, altitude, launch_height_m, camera, masks or seed or
a scan's best frames, start_s, end_s, fps, quality, …); a project file gives every animal of
its clips, fitted with the animal's fit settings and measured on the frames measured in the
app. Every row is checked before anything
runs (a bad cell: exit 2, naming the row and column).

Each task fits the 3D model (`dolphinfit fit`'s outputs) and measures the elliptical baseline
into DIR/<clip key>_<animal>/ (default DIR: INPUT_batch beside the input), with task.json
recording its inputs' content hashes and its status; the folder appears only once complete.
A rerun skips finished tasks whose inputs did not change, and failed ones unless
--retry-failed; a killed batch rerun finishes the rest. DIR/summary.csv: one row per clip and
animal with both methods' length, volume, BCI, density and mass (elliptical 95 % intervals),
status and error.

Runs on a LocalCluster of --workers worker processes (default: as many as the cores and memory
allow), or on the Dask scheduler at --scheduler (e.g. a dask-jobqueue SLURM or PBS cluster's).
Each worker's torch uses --threads threads (default: the cores shared out), never more than
cores / workers. --device is where each worker's fits compute (auto, the default: a CUDA GPU
where that worker's torch sees one, else the CPU); on the local cluster cuda is refused at
once where torch sees no GPU, on a scheduler's workers each task records it. The local
cluster's workers share one GPU. Exit codes: 0 every task complete; 1 some failed (see the
summary); 2 bad input.
"""

import argparse
import os
import sys
from collections.abc import Callable
from pathlib import Path

from dolphinfit.core.batch.cluster import ClusterPlan, batch_client, local_plan
from dolphinfit.core.batch.manifest import read_manifest
from dolphinfit.core.batch.project_tasks import project_tasks
from dolphinfit.core.batch.record import STATUS_COMPLETE, TaskRecord
from dolphinfit.core.batch.summary import SUMMARY_CSV
from dolphinfit.core.batch.runner import run_batch
from dolphinfit.core.batch.task import BatchTask, check_unique_names
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.output_paths import check_output_folder
from dolphinfit.core.limits import count
from dolphinfit.core.measure.uncertainty import DEFAULT_NUM_DRAWS
from dolphinfit.core.progress import Progress
from dolphinfit.core.project.project_file import PROJECT_SUFFIX
from dolphinfit.core.runtime import THREADS_ENV, thread_count
from dolphinfit.app.commands.device_option import add_device_argument, chosen_device
from dolphinfit.app.progress import terminal_progress

OUT_SUFFIX = "_batch"  # default output folder: INPUT_batch beside the input


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The input and the options of the module docstring."""
    parser.add_argument("input", type=Path, help="a manifest CSV or a project (.dolphinfit)")
    parser.add_argument("--out", type=Path, default=None, metavar="DIR",
                        help="output folder (default: INPUT_batch beside the input)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="a running Dask scheduler, e.g. tcp://10.0.0.5:8786")
    where.add_argument("--workers", type=int, default=None, metavar="N",
                       help="worker processes of the local cluster (default: by cores and "
                            "memory)")
    parser.add_argument("--retry-failed", action="store_true",
                        help="run failed tasks again (default: keep their record)")
    parser.add_argument("--mc", type=int, default=DEFAULT_NUM_DRAWS, metavar="N",
                        help="Monte Carlo draws of the elliptical intervals (default: "
                             "%(default)s)")
    add_device_argument(parser, "where each worker's fits compute")


def tasks_of(path: Path, num_draws: int) -> list[BatchTask]:
    """The tasks of a manifest or a project file."""
    tasks = (project_tasks(path, num_draws) if path.suffix == PROJECT_SUFFIX
             else read_manifest(path, num_draws))
    return check_unique_names(tasks)


def _threads(args: argparse.Namespace) -> int | None:
    """Torch threads per worker asked for (--threads, $DOLPHINFIT_THREADS), else None."""
    if args.threads is None and THREADS_ENV not in os.environ:
        return None
    return thread_count(args.threads)


def run(args: argparse.Namespace) -> int:
    """Plan, run on the cluster, write and print the summary."""
    count(args.mc, 0, "--mc")
    if args.mc == 1:
        raise InputError("--mc must be 0 (no Monte Carlo) or at least 2, got 1")
    if not args.scheduler:   # the local workers' torch is this one: refused before any work
        chosen_device(args)
    tasks = tasks_of(args.input, args.mc)
    out_dir = args.out or args.input.with_name(args.input.stem + OUT_SUFFIX)
    check_output_folder(out_dir, "--out ")
    threads = _threads(args)
    plan = (ClusterPlan(None, threads or 1) if args.scheduler
            else local_plan(args.workers, threads))
    is_terminal = sys.stderr.isatty()   # where the progress line is drawn
    with batch_client(args.scheduler, plan) as client:
        workers = len(client.scheduler_info()["workers"])
        print(f"{len(tasks)} tasks on {workers} Dask workers × {plan.torch_threads} torch "
              f"thread(s) → {out_dir}")
        if client.dashboard_link:
            print(f"Dask dashboard: {client.dashboard_link}")
        show = _progress_bar if is_terminal else _line
        records = run_batch(client, tasks, out_dir, args.retry_failed,
                            on_record=show(len(tasks)), device=args.device)
    return report(records, out_dir / SUMMARY_CSV)


def _progress_bar(total: int) -> Callable[[int, TaskRecord], None]:
    """The commands' one-line progress display (app/progress.py), a step per finished task
    (on a terminal)."""
    done: list[TaskRecord] = []
    show_line = terminal_progress() or (lambda progress: None)

    def show(_: int, record: TaskRecord) -> None:
        done.append(record)
        failed = sum(r.status != STATUS_COMPLETE for r in done)
        show_line(Progress("batch", len(done), total, f"tasks, {failed} failed"))

    return show


def _line(total: int) -> Callable[[int, TaskRecord], None]:
    """A line per finished task on stdout (when stderr, where the progress line is drawn, is
    not a terminal)."""
    done: list[TaskRecord] = []

    def show(_: int, record: TaskRecord) -> None:
        done.append(record)
        reused = " (finished before)" if record.reused else ""
        error = f": {record.error}" if record.error else ""
        print(f"[{len(done)}/{total}] {record.clip} {record.animal_id}: {record.status}"
              f"{reused}{error}", flush=True)

    return show


def report(records: list[TaskRecord], summary: Path) -> int:
    """Print the counts and the failures; the exit code (module docstring)."""
    failed = [r for r in records if r.status != STATUS_COMPLETE]
    reused = sum(r.reused for r in records)
    print(f"{len(records) - len(failed)} complete ({reused} finished before), "
          f"{len(failed)} failed; summary: {summary}")
    for record in failed:
        print(f"failed: {record.clip} {record.animal_id}: {record.error}", file=sys.stderr)
    return 1 if failed else 0
