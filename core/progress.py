"""The progress and cancel contract of every long job in core (fit, tracker, synthetic clips,
Monte Carlo, exports).

Progress: the job calls ``progress(Progress(...))`` from its own thread, at least once a
second while it works. ``step`` counts the job's units of work (optimisation steps, frames,
draws) and never decreases or exceeds ``total``; a job that finishes reports ``step == total``
last. ``stage`` names what the job is doing, ``message`` says it in words, ``eta_s`` is the
remaining time estimated from the measured rate (None until there is a rate) and ``metrics``
carries numbers worth showing (losses, IoU). ``preview``, when a job has one, is a snapshot of
its current state for display (the fit's: a core.fit.reporter.FitPreview, at most about once a
second); consumers must not keep it beyond showing it.

Cancel: the caller passes a ``threading.Event``; the job checks it between units of work
(``check_cancel``) and raises :class:`Cancelled` once it is set, leaving no partial output,
unless its documentation says it returns what it has instead (the fit keeps its best state).
"""

import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace


@dataclass(frozen=True)
class Progress:
    """Where a long job is (module docstring)."""

    stage: str
    step: int
    total: int
    message: str = ""
    eta_s: float | None = None
    metrics: Mapping[str, float] = field(default_factory=dict)
    preview: object | None = None

    @property
    def fraction(self) -> float:
        """step / total in [0, 1]; 1 for a job with nothing to do."""
        return min(1.0, self.step / self.total) if self.total > 0 else 1.0


ProgressCallback = Callable[[Progress], None]


class Cancelled(Exception):
    """The caller asked the work to stop."""


def check_cancel(cancel: threading.Event | None) -> None:
    """Raise Cancelled if ``cancel`` is set."""
    if cancel is not None and cancel.is_set():
        raise Cancelled()


def part_of(progress: ProgressCallback | None, offset: int,
            total: int) -> ProgressCallback | None:
    """Reports of a part of a larger job, as steps ``offset + step`` of that job's ``total``."""
    if progress is None:
        return None
    return lambda part: progress(replace(part, step=offset + part.step, total=total))
