"""``dolphinfit bench batch --faults``: ``dolphinfit batch`` under faults. Many tiny tasks run
on a LocalCluster of 2 workers in a child process; once some are done one worker process is
killed (SIGKILL), later the batch process itself with the scheduler it holds, and the same
command is run again to the end. Then every task must have a record, complete or, for the
tenth of them given no masks, failed with a reason; the summary must hold a row per task,
the rerun reuse exactly the tasks finished before it, and no task may have been completed
twice (core/bench/record_watch.py counts completions on disk while the batch runs).
"""

import csv
import os
import subprocess
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path

import psutil
from dask.system import CPU_COUNT

from dolphinfit.core.batch.manifest import read_manifest
from dolphinfit.core.batch.record import STATUS_COMPLETE, read_record
from dolphinfit.core.batch.summary import SUMMARY_CSV
from dolphinfit.core.bench.batch_bench import TINY_CLIP, TINY_CLIP_CONFIG, write_synthetic_batch
from dolphinfit.core.bench.record_watch import RecordWatch

# One tiny clip listed under many animal IDs: each row a task of its own folder
DRILL_TASKS = 120
FAIL_EVERY = 10  # every 10th task has an empty masks folder: its fit fails
MIN_TASKS = 4  # a worker kill, two tasks more, then the batch kill before the last
MC_DRAWS = 50
POLL_S = 0.05
STALL_S = 120.0  # the first run with no task ending for this long: hung
RERUN_LIMIT_S = 900.0
EXIT_WAIT_S = 10.0  # how long a killed batch's workers get to end on their own


def _kill_points(tasks: int) -> tuple[int, int]:
    """Tasks done when a worker is killed, and when the batch is."""
    worker_at = max(1, tasks // 4)
    return worker_at, max(worker_at + 2, 3 * tasks // 5)


def _workers(batch: psutil.Process) -> list[psutil.Process]:
    """The batch's Dask worker processes (multiprocessing spawns them), by pid."""
    found = []
    for child in batch.children(recursive=True):
        try:
            if any("spawn_main" in part for part in child.cmdline()):
                found.append(child)
        except psutil.Error:
            continue
    return sorted(found, key=lambda p: p.pid)


def _wait_gone(processes: list[psutil.Process], limit_s: float,
               meanwhile: Callable[[], object]) -> list[psutil.Process]:
    """Wait up to ``limit_s`` for ``processes`` to end, calling ``meanwhile`` between looks;
    those still running."""
    end = time.monotonic() + limit_s
    alive = processes
    while alive and time.monotonic() < end:
        meanwhile()
        alive = [p for p in alive if _running(p)]
        time.sleep(POLL_S)
    return alive


def _running(process: psutil.Process) -> bool:
    try:
        return process.status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def _fail_some(manifest: Path) -> None:
    """Point every ``FAIL_EVERY``-th row of ``manifest`` (written by ``write_synthetic_batch``
    for one clip) at an empty masks folder."""
    (manifest.parent / "no_masks").mkdir()
    header, *rows = manifest.read_text().splitlines()
    rows = [row.replace(",clip0/masks,", ",no_masks,") if i % FAIL_EVERY == FAIL_EVERY - 1
            else row for i, row in enumerate(rows)]
    manifest.write_text("\n".join([header, *rows]) + "\n")


def _batch_command(manifest: Path, out: Path, workers: int) -> list[str]:
    return [sys.executable, "-m", "dolphinfit.app.cli", "--threads", "1", "batch", str(manifest),
            "--out", str(out), "--workers", str(workers), "--mc", str(MC_DRAWS)]


class Drill:
    """One drill in ``folder``: the batch's command, its output and the watch on it."""

    def __init__(self, folder: Path, tasks: int, workers: int) -> None:
        self.folder = folder
        manifest = write_synthetic_batch(folder / "input", [TINY_CLIP], TINY_CLIP_CONFIG,
                                         animals=tasks)
        _fail_some(manifest)
        self.names = [task.name for task in read_manifest(manifest, MC_DRAWS)]
        self.failing = set(self.names[FAIL_EVERY - 1::FAIL_EVERY])
        self.out = folder / "out"
        self.command = _batch_command(manifest, self.out, workers)
        self.env = {**os.environ, "DASK_TEMPORARY_DIRECTORY": str(folder / "dask")}
        self.watch = RecordWatch(self.out, self.names)
        self.problems: list[str] = []

    def start(self, log_name: str) -> subprocess.Popen:
        with open(self.folder / log_name, "wb") as log:
            return subprocess.Popen(self.command, stdout=log, stderr=subprocess.STDOUT,
                                    env=self.env)

    def log_tail(self, log_name: str) -> str:
        lines = (self.folder / log_name).read_text(errors="replace").strip().splitlines()
        return lines[-1] if lines else "no output"

    def first_run(self) -> dict:
        """Run until a worker and then the batch are killed; the kills."""
        worker_at, batch_at = _kill_points(len(self.names))
        start = time.monotonic()
        batch = self.start("run1.log")
        process = psutil.Process(batch.pid)
        kills: dict = {}
        done, last_change = 0, start
        while batch.poll() is None:
            now = time.monotonic()
            if (count := self.watch.poll()) != done:
                done, last_change = count, now
            if now - last_change > STALL_S:
                self.problems.append(f"the first run hung: no task ended for {STALL_S:.0f} s "
                                     f"after {done} tasks")
                break
            if "worker" not in kills and done >= worker_at:
                kills["worker"] = self._kill_worker(process, done, now - start)
            elif "worker" in kills and done >= batch_at:
                break
            time.sleep(POLL_S)
        if batch.poll() is not None:
            self.problems.append(f"the first run ended (exit {batch.returncode}: "
                                 f"{self.log_tail('run1.log')}) before its batch was killed")
            return kills
        if "pid" in kills.get("worker", {}):
            replaced = {p.pid for p in _workers(process)} - set(kills["worker"]["worker_pids"])
            kills["worker"]["replaced"] = bool(replaced)
        kills["batch"] = {"at_s": time.monotonic() - start, "tasks_done": done,
                          **self._kill_batch(batch, process)}
        return kills

    def _kill_worker(self, batch: psutil.Process, done: int, at_s: float) -> dict:
        workers = _workers(batch)
        if not workers:
            self.problems.append("no Dask worker process found to kill")
            return {"worker_pids": []}
        workers[0].kill()
        left = _wait_gone(workers[:1], EXIT_WAIT_S, self.watch.poll)
        if left:
            self.problems.append(f"the killed worker {workers[0].pid} is still running")
        return {"pid": workers[0].pid, "at_s": at_s, "tasks_done": done,
                "worker_pids": [p.pid for p in workers]}

    def _kill_batch(self, batch: subprocess.Popen, process: psutil.Process) -> dict:
        """Kill the batch process, which holds the LocalCluster's scheduler; its workers must
        end by themselves (those left are killed and counted)."""
        family = process.children(recursive=True)
        batch.kill()
        batch.wait()
        start = time.monotonic()
        left = _wait_gone(family, EXIT_WAIT_S, self.watch.poll)
        for stray in left:
            stray.kill()
        if left:
            self.problems.append(f"{len(left)} process(es) of the killed batch were still "
                                 f"running {EXIT_WAIT_S:.0f} s later")
        return {"processes_left": len(left), "processes_gone_s": time.monotonic() - start}

    def rerun(self) -> int | None:
        """Run the same command to the end; its exit code (None: it ran past the limit)."""
        batch = self.start("run2.log")
        process = psutil.Process(batch.pid)
        end = time.monotonic() + RERUN_LIMIT_S
        while batch.poll() is None:
            self.watch.poll()
            if time.monotonic() > end:
                self._kill_batch(batch, process)
                self.problems.append(f"the rerun hung: not done after {RERUN_LIMIT_S:.0f} s")
                return None
            time.sleep(POLL_S)
        self.watch.poll()
        expected = 1 if self.failing else 0  # 1: some task failed
        if batch.returncode != expected:
            self.problems.append(f"the rerun exited {batch.returncode}, not {expected}: "
                                 f"{self.log_tail('run2.log')}")
        return batch.returncode

    def outcome(self, before_rerun: dict) -> dict:
        """Records, summary rows, reuse and completions, against what must hold."""
        records = {name: read_record(self.out / name) for name in self.names}
        missing = [name for name, r in records.items() if r is None]
        failed = [r for r in records.values() if r is not None and r.status != STATUS_COMPLETE]
        unexplained = [r.name for r in failed if not r.error.strip()]
        complete = {name for name, r in records.items()
                    if r is not None and r.status == STATUS_COMPLETE}
        rows = _summary_rows(self.out / SUMMARY_CSV)
        folders = Counter(row["folder"] for row in rows)
        reused = {row["folder"] for row in rows if row["reused"] == "yes"}
        finished_before = set(before_rerun)
        after = self.watch.current()
        changed = sorted(n for n in finished_before if after.get(n) != before_rerun[n])
        completions = self.watch.completions()
        twice = sorted(name for name, n in completions.items() if n > 1)
        partial = sorted(p.name for p in self.out.iterdir() if p.name.startswith("."))
        checks = {
            "task(s) without a record": missing,
            "failed task(s) without a reason": unexplained,
            "task(s) with good inputs not complete": sorted(set(self.names) - self.failing
                                                            - complete - set(missing)),
            "task(s) without masks complete": sorted(self.failing & complete),
            "task(s) without a summary row": sorted(set(self.names) - set(folders)),
            "summary row(s) twice": sorted(f for f, n in folders.items() if n > 1),
            "task(s) finished before the rerun not reported reused":
                sorted(finished_before - reused),
            "task(s) run by the rerun reported reused": sorted(reused - finished_before),
            "task(s) finished before the rerun written again": changed,
            "task(s) completed more than once": twice,
            "partial folder(s) left": partial,
        }
        self.problems += [f"{len(names)} {what}: {', '.join(names[:5])}"
                          for what, names in checks.items() if names]
        return {"complete": len(complete),
                "failed": len(failed), "failures": dict(Counter(r.error for r in failed)),
                "without_record": len(missing), "summary_rows": len(rows),
                "finished_before_rerun": len(finished_before), "reused_on_rerun": len(reused),
                "completions_per_task": {"max": max(completions.values()),
                                         "min": min(completions.values()),
                                         "tasks_completed_twice": len(twice)},
                "partial_folders_left": len(partial)}


def _summary_rows(path: Path) -> list[dict[str, str]]:
    if not path.is_file():
        return []
    with open(path, newline="") as file:
        return list(csv.DictReader(file))


def drill_batch_faults(tasks: int = DRILL_TASKS, workers: int = min(2, CPU_COUNT)) -> dict:
    """Run the drill of the module docstring with ``tasks`` tasks; its figures, with
    ``problems`` (none: ``passed``)."""
    start = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="dolphinfit-bench-faults-") as tmp:
        drill = Drill(Path(tmp), tasks, workers)
        setup_s = time.monotonic() - start
        kills = drill.first_run()
        first_s = time.monotonic() - start - setup_s
        before_rerun = drill.watch.current()
        rerun_exit = drill.rerun()
        rerun_s = time.monotonic() - start - setup_s - first_s
        outcome = drill.outcome(before_rerun)
    return {"tasks": tasks, "workers": workers,
            "clip": {"width_px": TINY_CLIP.width_px, "height_px": TINY_CLIP.height_px,
                     "duration_s": TINY_CLIP.duration_s},
            "fit": {"fps": TINY_CLIP_CONFIG.fps, "steps": TINY_CLIP_CONFIG.total_steps},
            "kills": kills, "rerun_exit_code": rerun_exit, **outcome,
            "phases_s": {"setup": setup_s, "first_run": first_s, "rerun": rerun_s,
                         "total": time.monotonic() - start},
            "passed": not drill.problems, "problems": drill.problems}
