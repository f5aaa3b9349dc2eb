"""Results of the current frame and animal, computed in one worker thread, newest request only.

Every model change (each step of a handle drag) asks for a new result. Phase 1, the nominal
estimate, takes milliseconds and is delivered at once; phase 2, the Monte Carlo interval, starts
only once no newer request has come for ``debounce_s``, so a drag never queues Monte Carlo
runs. Work made stale by a newer request is dropped between phases and before delivery.
The Monte Carlo seed is fixed, so the same measurement always shows the same interval.
"""

import logging
import threading
import time
from pathlib import Path
from dataclasses import dataclass

from PySide6.QtCore import QObject, Qt, Signal, Slot

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.elliptical import NoWidthError
from dolphinfit.core.measure.hw_ratios import HWRatios
from dolphinfit.core.model.hw_spec import resolve_hw
from dolphinfit.core.measure.uncertainty import DEFAULT_NUM_DRAWS
from dolphinfit.core.project.model import MeasurementKey, Project
from dolphinfit.core.project.results import (
    FrameResult, LengthResult, Spread, animal_summary, measure_frame, measure_length,
    project_hw_spec,
)

log = logging.getLogger(__name__)

DEBOUNCE_S = 0.3
SEED = 0
NOMINAL, INTERVAL, FAILED, ANIMAL = "nominal", "interval", "failed", "animal"


@dataclass(frozen=True)
class AnimalSummary:
    """Spread of each SUMMARY_KEYS quantity over an animal's measurable frames (empty when
    none is), and how many measured frames were left out (no length, no width, no altitude)."""

    request_id: int
    clip_idx: int
    animal_idx: int
    animal_id: str
    spreads: dict[str, Spread]
    num_left_out: int


@dataclass(frozen=True)
class _FrameJob:
    request_id: int
    project: Project
    key: MeasurementKey
    altitude_m: float
    altitude_source: str
    due_s: float  # monotonic time from which the Monte Carlo may start


@dataclass(frozen=True)
class _AnimalJob:
    request_id: int
    project: Project
    clip_idx: int
    animal_idx: int
    altitudes: dict[int, tuple[float, str]]


class ResultsWorker(QObject):
    """Computes FrameResults off the GUI thread; signals arrive on the GUI thread.

    ``request`` and ``request_animal`` return the request's id, which the signals carry (the
    animal's inside its AnimalSummary). Call ``shutdown()`` when the owner closes.
    """

    # request id, FrameResult (LengthResult while the frame has no width) without interval
    nominal_ready = Signal(int, object)
    interval_ready = Signal(int, object)  # request id, the same with the Monte Carlo
    failed = Signal(int, str)             # request id, why the frame cannot be measured
    animal_ready = Signal(object, object)  # list[FrameResult], AnimalSummary
    _computed = Signal(str, int, object)  # kind, request id, payload (worker → GUI thread)

    def __init__(self, num_draws: int = DEFAULT_NUM_DRAWS, debounce_s: float = DEBOUNCE_S,
                 parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.num_draws = num_draws
        self.project_dir: Path | None = None  # where HW-table CSVs of the project are relative to
        self._debounce_s = debounce_s
        self._cond = threading.Condition()
        self._frame_job: _FrameJob | None = None
        self._is_nominal_done = False
        self._animal_job: _AnimalJob | None = None
        self._is_stopping = False
        self._last_id = 0          # GUI thread: the newest request of each kind
        self._last_animal_id = 0
        self._hw_cache: dict[str, HWRatios] = {}  # worker thread only
        self._computed.connect(self._deliver, Qt.ConnectionType.QueuedConnection)
        self._thread = threading.Thread(target=self._serve, name="ResultsWorker", daemon=True)
        self._thread.start()

    # ----- GUI thread
    def request(self, project: Project, key: MeasurementKey, altitude_m: float,
                altitude_source: str) -> int:
        """Ask for the result of one measured frame; replaces any pending frame request."""
        with self._cond:
            self._last_id += 1
            self._frame_job = _FrameJob(self._last_id, project, key, altitude_m,
                                        altitude_source, time.monotonic() + self._debounce_s)
            self._is_nominal_done = False
            self._cond.notify()
            return self._last_id

    def request_animal(self, project: Project, clip_idx: int, animal_idx: int,
                       altitudes: dict[int, tuple[float, str]]) -> int:
        """Ask for the nominal results of an animal's measured frames; ``altitudes`` maps a
        frame index to (altitude m, source). Replaces any pending animal request."""
        with self._cond:
            self._last_animal_id += 1
            self._animal_job = _AnimalJob(self._last_animal_id, project, clip_idx, animal_idx,
                                          dict(altitudes))
            self._cond.notify()
            return self._last_animal_id

    def cancel(self) -> None:
        """Drop the pending frame request (nothing to show); its results in flight are
        ignored."""
        with self._cond:
            self._last_id += 1
            self._frame_job = None

    def shutdown(self) -> None:
        """Drop pending work and join the thread (after the computation in flight)."""
        with self._cond:
            self._is_stopping = True
            self._cond.notify()
        self._thread.join()

    @Slot(str, int, object)
    def _deliver(self, kind: str, request_id: int, payload: object) -> None:
        if kind == ANIMAL:
            if request_id == self._last_animal_id:
                self.animal_ready.emit(*payload)
        elif request_id == self._last_id:
            {NOMINAL: self.nominal_ready, INTERVAL: self.interval_ready,
             FAILED: self.failed}[kind].emit(request_id, payload)

    # ----- worker thread
    def _next_task(self) -> tuple[str, _FrameJob | _AnimalJob] | None:
        """Wait for the next task: a nominal result, an animal, then a due Monte Carlo."""
        with self._cond:
            while not self._is_stopping:
                job = self._frame_job
                if job is not None and not self._is_nominal_done:
                    self._is_nominal_done = True
                    return NOMINAL, job
                if self._animal_job is not None:
                    animal, self._animal_job = self._animal_job, None
                    return ANIMAL, animal
                if job is None:
                    self._cond.wait()
                elif (wait_s := job.due_s - time.monotonic()) > 0:
                    self._cond.wait(wait_s)
                else:
                    self._frame_job = None
                    return INTERVAL, job
            return None

    def _is_current(self, job: _FrameJob | _AnimalJob) -> bool:
        with self._cond:
            current = self._animal_job if isinstance(job, _AnimalJob) else self._frame_job
            return current is None or current.request_id == job.request_id

    def _serve(self) -> None:
        while (task := self._next_task()) is not None:
            kind, job = task
            if kind == ANIMAL:
                try:
                    self._computed.emit(ANIMAL, job.request_id, self._animal_results(job))
                except Exception:  # the frame request reports the cause; keep serving
                    log.exception("results worker: animal summary failed")
                continue
            try:
                result = self._measure(job, 0 if kind == NOMINAL else self.num_draws)
            except (InputError, ValueError) as exc:
                self._drop_interval(job)
                self._computed.emit(FAILED, job.request_id, str(exc))
            except Exception as exc:  # an internal error still reaches the user, as a message
                log.exception("results worker failed")
                self._drop_interval(job)
                self._computed.emit(FAILED, job.request_id, f"internal error: {exc!r}")
            else:
                if self._is_current(job):
                    self._computed.emit(kind, job.request_id, result)

    def _drop_interval(self, job: _FrameJob | _AnimalJob) -> None:
        """No Monte Carlo after a failed nominal result."""
        with self._cond:
            if self._frame_job is job:
                self._frame_job = None

    def _hw(self, name: str) -> HWRatios:
        if name not in self._hw_cache:
            self._hw_cache[name] = resolve_hw(name)
        return self._hw_cache[name]

    def _measure(self, job: _FrameJob, num_draws: int) -> FrameResult | LengthResult:
        """The frame's estimate; its length alone while it has no width."""
        try:
            return measure_frame(job.project, job.key, job.altitude_m, job.altitude_source,
                                 self._hw(project_hw_spec(job.project, self.project_dir)),
                                 num_draws, SEED)
        except NoWidthError:
            return measure_length(job.project, job.key, job.altitude_m, job.altitude_source,
                                  num_draws, SEED)

    def _animal_results(self, job: _AnimalJob) -> tuple[list[FrameResult], AnimalSummary]:
        """Nominal results of the animal's frames; frames that cannot be measured left out
        (all of them when the HW table cannot be read: the frame request reports why)."""
        animal = job.project.clips[job.clip_idx].animals[job.animal_idx]
        results = []
        for m, measurement in enumerate(animal.measurements):
            if measurement.frame_idx not in job.altitudes or not self._is_current(job):
                continue
            altitude_m, source = job.altitudes[measurement.frame_idx]
            key = MeasurementKey(job.clip_idx, job.animal_idx, m)
            try:
                results.append(measure_frame(job.project, key, altitude_m, source,
                                             self._hw(project_hw_spec(job.project,
                                                                      self.project_dir)),
                                             0, SEED))
            except (InputError, ValueError):
                continue
        return results, AnimalSummary(job.request_id, job.clip_idx, job.animal_idx,
                                      animal.animal_id, animal_summary(results) if results else {},
                                      len(animal.measurements) - len(results))
