"""``dolphinfit bench batch --faults``: `dolphinfit batch` with a worker and then the batch
with its scheduler killed, rerun to the end, and checked (core/bench/batch_faults.py).

  dolphinfit bench batch --faults [--tasks N] [--json]

Exit code 0 when every check holds, 1 when one does not (the table names it).
"""

import argparse

from dolphinfit.app.commands.bench_output import emit
from dolphinfit.core.bench.batch_faults import DRILL_TASKS, MIN_TASKS, drill_batch_faults
from dolphinfit.core.limits import count


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The drill's options, on ``bench batch``."""
    parser.add_argument("--faults", action="store_true",
                        help="the fault drill instead: a worker killed, then the batch with "
                             "its scheduler, the batch rerun and checked")
    parser.add_argument("--tasks", type=int, default=None, metavar="N",
                        help=f"--faults: tiny tasks in the batch (default {DRILL_TASKS})")


def run(args: argparse.Namespace) -> int:
    """Run the drill, print its figures; 1 when a check failed."""
    tasks = DRILL_TASKS if args.tasks is None else count(args.tasks, MIN_TASKS, "--tasks")
    figures = drill_batch_faults(tasks)
    emit(args, figures, format_faults)
    return 0 if figures["passed"] else 1


def format_faults(f: dict) -> str:
    """The kills, the phases, the tasks' ends and the checks."""
    kills, phases = f["kills"], f["phases_s"]
    lines = [f"{f['tasks']} tasks (one {f['clip']['width_px']}×{f['clip']['height_px']} clip "
             f"of {f['clip']['duration_s']:g} s, {f['fit']['steps']} fit steps at "
             f"{f['fit']['fps']:g} frames/s) on {f['workers']} Dask workers"]
    if "pid" in kills.get("worker", {}):
        worker = kills["worker"]
        lines.append(f"worker {worker['pid']} killed at {worker['at_s']:.1f} s, "
                     f"{worker['tasks_done']} tasks done; replaced: "
                     f"{'yes' if worker.get('replaced') else 'no'}")
    if "batch" in kills:
        batch = kills["batch"]
        lines.append(f"batch and its scheduler killed at {batch['at_s']:.1f} s, "
                     f"{batch['tasks_done']} tasks done; its workers gone "
                     f"{batch['processes_gone_s']:.1f} s later, {batch['processes_left']} left")
    lines += [
        f"phases: setup {phases['setup']:.1f} s, first run {phases['first_run']:.1f} s, "
        f"rerun {phases['rerun']:.1f} s (exit {f['rerun_exit_code']}), total "
        f"{phases['total']:.1f} s",
        f"tasks: {f['complete']} complete, {f['failed']} failed, {f['without_record']} without "
        f"a record; summary: {f['summary_rows']} rows",
        *(f"  failed ×{n}: {reason}" for reason, n in f["failures"].items()),
        f"rerun: {f['reused_on_rerun']} reused of {f['finished_before_rerun']} finished before",
        f"completions per task: max {f['completions_per_task']['max']}, min "
        f"{f['completions_per_task']['min']}; partial folders left: "
        f"{f['partial_folders_left']}",
        "passed" if f["passed"] else "FAILED:",
        *(f"  {problem}" for problem in f["problems"]),
    ]
    return "\n".join(lines)
