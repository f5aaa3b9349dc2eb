"""Process-wide runtime settings: torch's CPU thread count.

On a 2-core machine oversubscription is far worse than one thread (reference/platform.md §8),
so the count is always set explicitly: from the caller, else ``DOLPHINFIT_THREADS``, else 2.
"""

import os

import torch

from core.errors import InputError
from core.limits import count

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
