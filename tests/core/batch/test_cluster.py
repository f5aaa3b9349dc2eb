"""The local cluster's size: workers × torch threads never exceed the cores."""

import pytest

from core.batch.cluster import WORKER_MEMORY_BYTES, ClusterPlan, local_plan
from core.errors import InputError


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
