"""A one-line progress display on a terminal for the commands' long jobs (core.progress)."""

import sys

from dolphinfit.core.progress import Progress, ProgressCallback

PROGRESS_LINES = 10  # lines a plain (non-terminal) progress report prints per job


def terminal_progress() -> ProgressCallback | None:
    """A callback redrawing one stderr line per report (a new line per stage and after the
    last step); None when stderr is not a terminal."""
    if not sys.stderr.isatty():
        return None
    shown = {"stage": None, "is_open": False}

    def show(progress: Progress) -> None:
        if shown["is_open"] and progress.stage != shown["stage"]:
            print(file=sys.stderr)
        eta = "" if progress.eta_s is None else f"  ETA {progress.eta_s:4.0f} s"
        is_done = progress.step >= progress.total
        print(f"\r{progress.stage:8s} {progress.step:5d}/{progress.total}{eta}  "
              f"{progress.message}".ljust(78), end="\n" if is_done else "", file=sys.stderr,
              flush=True)
        shown.update(stage=progress.stage, is_open=not is_done)

    return show


def is_tenth(progress: Progress) -> bool:
    """Whether a report falls on one of ``PROGRESS_LINES`` evenly spaced steps of its job (or
    is its last): where a command's plain progress line is printed."""
    step = max(1, progress.total // PROGRESS_LINES)
    return progress.step % step == 0 or progress.step == progress.total
