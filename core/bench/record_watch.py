"""Counting how many times each task of a running batch was completed, from outside it.

Every completion of a task writes a new ``task.json`` (the task's folder is filled beside it
and swapped in whole: core/io/atomic.py), so each completion leaves a file of its own inode
and modification time. Polling them tells completions apart; two completions of one task
within one poll (a few tens of milliseconds) would count as one.
"""

from collections.abc import Sequence
from pathlib import Path

from dolphinfit.core.batch.record import RECORD_JSON

Identity = tuple[int, int]  # a task.json's inode and modification time (ns)


class RecordWatch:
    """The ``task.json`` files seen in each task's folder under ``out_dir``."""

    def __init__(self, out_dir: Path, names: Sequence[str]) -> None:
        self.paths = {name: Path(out_dir) / name / RECORD_JSON for name in names}
        self.seen: dict[str, set[Identity]] = {name: set() for name in names}

    def current(self) -> dict[str, Identity]:
        """The record of each task that has one now."""
        now = {}
        for name, path in self.paths.items():
            try:
                stat = path.stat()
            except OSError:  # none yet, or its folder is being swapped
                continue
            now[name] = (stat.st_ino, stat.st_mtime_ns)
        return now

    def poll(self) -> int:
        """Look once and remember what is there; how many tasks have a record."""
        now = self.current()
        for name, identity in now.items():
            self.seen[name].add(identity)
        return len(now)

    def completions(self) -> dict[str, int]:
        """The records seen per task: its completions."""
        return {name: len(seen) for name, seen in self.seen.items()}
