"""Timing and memory helpers for the benchmarks."""

import json
import subprocess
import sys
import time
from collections.abc import Callable, Sequence


def median_ms(run: Callable[[], object], repeats: int, warmup: int = 1) -> float:
    """Median wall time of ``run`` in milliseconds after ``warmup`` untimed calls."""
    def timed() -> tuple[float]:
        start = time.perf_counter()
        run()
        return (time.perf_counter() - start,)

    return median_phases_ms(timed, repeats, warmup)[1]


def median_phases_ms(run: Callable[[], Sequence[float]], repeats: int,
                     warmup: int = 1) -> tuple[list[float], float]:
    """Medians (ms) of each phase of ``run``, which returns the seconds each of its phases
    took, and the median of their sums: phases timed within the same repeats, so that a
    phase never comes out as the difference of two separately measured medians."""
    for _ in range(warmup):
        run()
    samples = [list(run()) for _ in range(repeats)]
    totals = sorted(sum(sample) for sample in samples)
    phases = [sorted(column)[len(column) // 2] for column in zip(*samples)]
    return [1e3 * phase for phase in phases], 1e3 * totals[len(totals) // 2]


def _status_mb(key: str) -> float:
    """A memory figure of this process from /proc/self/status (Linux), MB."""
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith(key):
                return int(line.split()[1]) / 1024
    raise OSError(f"{key} not in /proc/self/status")


def run_with_peak_rss_mb(job: Callable[[], object]) -> tuple[object, float]:
    """``job()``'s result and the peak resident memory (MB) it added, in this process.

    Resets the kernel's peak-RSS counter (``/proc/self/clear_refs``, Linux) before the job.
    """
    with open("/proc/self/clear_refs", "w") as clear:
        clear.write("5")
    before = _status_mb("VmRSS")
    result = job()
    return result, _status_mb("VmHWM") - before


def peak_rss_mb_of(module: str, function: str, *args: object) -> float:
    """Peak resident memory (MB) that running ``module.function(*args)()`` adds.

    In a fresh process the set-up ``function(*args)`` runs first; then the kernel's peak-RSS
    counter is reset (``/proc/self/clear_refs``, Linux) and the returned job runs. The result
    is the job's peak minus the resident memory just before it.
    """
    code = (
        "import json, sys, importlib\n"
        "def status(key):\n"
        "    for line in open('/proc/self/status'):\n"
        "        if line.startswith(key): return int(line.split()[1]) / 1024\n"
        f"mod = importlib.import_module({module!r})\n"
        f"job = getattr(mod, {function!r})(*json.loads(sys.argv[1]))\n"
        "open('/proc/self/clear_refs', 'w').write('5')\n"
        "before = status('VmRSS')\n"
        "job()\n"
        "print(json.dumps(status('VmHWM') - before))\n"
    )
    out = subprocess.run([sys.executable, "-c", code, json.dumps(list(args))],
                         capture_output=True, text=True, check=True)
    return float(json.loads(out.stdout.strip().splitlines()[-1]))


def command_seconds(argv: Sequence[str], repeats: int) -> list[float]:
    """Wall time (s) of each of ``repeats`` runs of the command ``argv``, start to exit.

    Raises RuntimeError with the command's error output when a run fails.
    """
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        done = subprocess.run(list(argv), capture_output=True, text=True)
        times.append(time.perf_counter() - start)
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(argv)} exited {done.returncode}: "
                               f"{done.stderr.strip()[-500:]}")
    return times
