"""Process-wide runtime settings: torch's CPU thread count, and single-thread workers.

On a 2-core machine oversubscription is far worse than one thread (reference/platform.md §8),
so the count is always set explicitly: from the caller, else ``DOLPHINFIT_THREADS``, else 2.
"""

import os
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager

import torch

from dolphinfit.core.errors import InputError
from dolphinfit.core.limits import count

THREADS_ENV = "DOLPHINFIT_THREADS"
DEFAULT_THREADS = 2


def thread_count(num_threads: int | None = None) -> int:
    """``num_threads``, else ``$DOLPHINFIT_THREADS``, else 2; InputError naming the
    variable, or "thread count", unless it is a whole number ≥ 1."""
    if num_threads is not None:
        return count(num_threads, 1, "thread count")
    text = os.environ.get(THREADS_ENV)
    if text is None:
        return DEFAULT_THREADS
    try:
        value = int(text)
    except ValueError:
        raise InputError(f"${THREADS_ENV} {text!r}: expected a whole number of threads, "
                         "at least 1") from None
    return count(value, 1, f"${THREADS_ENV}")


def configure_threads(num_threads: int | None = None) -> int:
    """Set torch's intra-op thread count (see :func:`thread_count`) and return it."""
    num_threads = thread_count(num_threads)
    torch.set_num_threads(num_threads)
    return num_threads


@contextmanager
def single_thread_workers(num_workers: int) -> Iterator[ThreadPoolExecutor | None]:
    """A pool of ``num_workers`` threads (None for one) for the block, torch at one intra-op
    thread in them and in the caller; the caller's count is restored after.

    Why: most of a fit's ops are too small for torch to split over cores (a second thread
    gains 1.12×), while independent chunks of work on one thread each scale nearly 2×, and
    each chunk's result is the same to the last bit whichever thread runs it. torch's count
    is process-wide: other threads of the process run on one thread meanwhile.
    """
    previous = torch.get_num_threads()
    torch.set_num_threads(1)
    pool = (ThreadPoolExecutor(num_workers, thread_name_prefix="dolphinfit-chunk",
                               initializer=torch.set_num_threads, initargs=(1,))
            if num_workers > 1 else None)
    try:
        yield pool
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
        torch.set_num_threads(previous)
