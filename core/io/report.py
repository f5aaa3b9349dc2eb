"""Small helpers for human-readable reports: short lists and runs of flagged frames."""

import numpy as np

MAX_LISTED = 5  # reports name at most this many items, then count the rest


def list_some(items: list[str]) -> str:
    """"a, b, c" for up to MAX_LISTED items, then "and N more"."""
    listed = ", ".join(items[:MAX_LISTED])
    more = len(items) - MAX_LISTED
    return listed + (f" and {more} more" if more > 0 else "")


def flag_runs(flags: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) indices, inclusive, of each run of True in a (T,) bool array."""
    padded = np.concatenate([[False], np.asarray(flags, dtype=bool), [False]])
    edges = np.flatnonzero(np.diff(padded.astype(np.int8)))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2])]


def format_runs(flags: np.ndarray) -> str:
    """"3, 10–14, 40–41" for the runs of True in ``flags`` (a few, then a count); "none"."""
    runs = flag_runs(flags)
    return list_some([f"{a}" if a == b else f"{a}–{b}" for a, b in runs]) if runs else "none"
