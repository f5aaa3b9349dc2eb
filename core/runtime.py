"""Process-wide runtime settings: torch's CPU thread count.

On a 2-core machine oversubscription is far worse than one thread (reference/platform.md §8),
so the count is always set explicitly: from the caller, else ``DOLPHINFIT_THREADS``, else 2.
"""

import os

import torch

THREADS_ENV = "DOLPHINFIT_THREADS"
DEFAULT_THREADS = 2


def configure_threads(num_threads: int | None = None) -> int:
    """Set torch's intra-op thread count and return it."""
    if num_threads is None:
        num_threads = int(os.environ.get(THREADS_ENV, DEFAULT_THREADS))
    if num_threads < 1:
        raise ValueError(f"thread count must be at least 1, got {num_threads}")
    torch.set_num_threads(num_threads)
    return num_threads
