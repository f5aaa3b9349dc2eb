"""The local cluster's size: workers × torch threads never exceed the cores."""

import pytest

from dolphinfit.core.batch.cluster import WORKER_MEMORY_BYTES, ClusterPlan, local_plan
from dolphinfit.core.errors import InputError


@pytest.mark.parametrize("workers, threads, cores, memory, plan", [
    (None, None, 8, 64 * WORKER_MEMORY_BYTES, ClusterPlan(8, 1)),
    (None, None, 8, 3 * WORKER_MEMORY_BYTES, ClusterPlan(3, 2)),   # memory-bound
    (None, None, 2, WORKER_MEMORY_BYTES // 2, ClusterPlan(1, 2)),  # at least one worker
    (2, None, 8, 64 * WORKER_MEMORY_BYTES, ClusterPlan(2, 4)),
    (3, 4, 8, 64 * WORKER_MEMORY_BYTES, ClusterPlan(3, 2)),        # threads lowered
    (1, 1, 8, 64 * WORKER_MEMORY_BYTES, ClusterPlan(1, 1)),
])
def test_local_plan_shares_the_cores(workers, threads, cores, memory, plan):
    assert local_plan(workers, threads, cores, memory) == plan
    assert plan.workers * plan.torch_threads <= cores


def test_more_workers_than_cores_is_refused():
    with pytest.raises(InputError, match="--workers 3: between 1 and the 2 cores"):
        local_plan(3, None, 2, 64 * WORKER_MEMORY_BYTES)


def test_an_interrupt_kills_the_local_workers_at_once():
    """Ctrl-C in a batch: the LocalCluster's worker processes are killed, not asked to
    finish a task that may run for minutes (Dask's close would wait 4 s, then kill): they
    are gone before the client and cluster close, which still happens, long before the
    task would have ended (within a tenth of it: a loaded machine's margin)."""
    import os
    import time

    import psutil

    from dolphinfit.core.batch import cluster as cluster_module
    from dolphinfit.core.batch.cluster import batch_client

    task_s = 60
    pids, gone_before_close = [], []

    def gone(pid: int) -> bool:
        try:
            return psutil.Process(pid).status() == psutil.STATUS_ZOMBIE
        except psutil.NoSuchProcess:
            return True

    def stop_then_look(cluster) -> None:
        real_stop(cluster)
        deadline = time.monotonic() + task_s / 10  # a SIGKILL lands in ms; a loaded machine
        while not all(map(gone, pids)) and time.monotonic() < deadline:
            time.sleep(0.05)
        gone_before_close.append(all(map(gone, pids)))

    real_stop = cluster_module.stop_workers
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(cluster_module, "stop_workers", stop_then_look)
        with pytest.raises(KeyboardInterrupt):
            with batch_client(plan=ClusterPlan(1, 1)) as client:
                pids.extend(client.run(os.getpid).values())
                assert pids and not any(map(gone, pids))
                busy = client.submit(time.sleep, task_s)  # a polite close would wait 4 s
                while not any(client.processing().values()):
                    time.sleep(0.05)
                stopped = time.monotonic()
                raise KeyboardInterrupt
    assert busy.status != "finished"
    assert gone_before_close == [True]   # killed by stop_workers, not by the close
    assert time.monotonic() - stopped < task_s / 10
    assert all(map(gone, pids))
