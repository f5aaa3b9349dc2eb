"""The Dask cluster a batch runs on: a LocalCluster sized to this machine, or a running
scheduler, with torch's thread count set in every worker so that workers × threads never
exceed the cores (oversubscription is far worse than one thread, reference/platform.md §8).

Each worker runs one task at a time (one Dask thread); its fit uses ``torch_threads`` threads.
"""

from collections.abc import Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass

import psutil
from dask.system import CPU_COUNT
from distributed import Client, LocalCluster, WorkerPlugin
from distributed.system import MEMORY_LIMIT

from dolphinfit.core.errors import InputError
from dolphinfit.core.runtime import configure_threads

# Memory one worker needs: a fit's peak (1.36 GB added on a 10 s, 1920×1080 clip, `bench fit
# --speed`) and the worker's own ~0.5 GB (Python, torch, the template).
WORKER_MEMORY_BYTES = 2 * 1024 ** 3


@dataclass(frozen=True)
class ClusterPlan:
    """Workers of a LocalCluster (None: a running scheduler's) and torch threads per worker."""

    workers: int | None
    torch_threads: int


def local_plan(workers: int | None = None, threads: int | None = None, cores: int = CPU_COUNT,
               memory_bytes: int = MEMORY_LIMIT) -> ClusterPlan:
    """Workers as many as the cores and the memory allow (or ``workers``), each with the
    cores shared out (or ``threads``, lowered to that share)."""
    if workers is None:
        workers = max(1, min(cores, memory_bytes // WORKER_MEMORY_BYTES))
    if not 1 <= workers <= cores:
        raise InputError(f"--workers {workers}: between 1 and the {cores} cores of this machine")
    share = cores // workers
    return ClusterPlan(workers, share if threads is None else min(threads, share))


class TorchThreads(WorkerPlugin):
    """Sets torch's thread count in each worker as it starts (workers joining later too)."""

    name = "dolphinfit-torch-threads"

    def __init__(self, threads: int) -> None:
        self.threads = threads

    def setup(self, worker: object) -> None:
        configure_threads(self.threads)


@contextmanager
def batch_client(scheduler: str | None = None, plan: ClusterPlan = ClusterPlan(None, 1),
                 processes: bool = True) -> Iterator[Client]:
    """A client of the scheduler at ``scheduler``, else of a LocalCluster of ``plan.workers``
    worker processes (threads when ``processes`` is False: tests); closed on exit."""
    if scheduler is not None:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError) as exc:
            raise InputError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
        cluster = None
    else:
        cluster = LocalCluster(n_workers=plan.workers, threads_per_worker=1,
                               processes=processes)
        client = Client(cluster)
    try:
        client.register_plugin(TorchThreads(plan.torch_threads))
        yield client
    except KeyboardInterrupt:
        if cluster is not None:
            stop_workers(cluster)
        raise
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def stop_workers(cluster: LocalCluster) -> None:
    """Kill the LocalCluster's worker processes: one busy in a fit answers a polite close
    only when its task ends (Dask waits 4 s, then kills it). A task's outputs are written
    whole or not at all, so nothing half-written is left."""
    for nanny in list(cluster.workers.values()):
        # a Nanny holds its worker in .process.process (workers as threads have none)
        process = getattr(getattr(nanny, "process", None), "process", None)
        if process is not None and process.pid is not None:
            with suppress(psutil.NoSuchProcess):
                psutil.Process(process.pid).kill()
