"""Background jobs deliver each outcome on the GUI thread and free each job's relay once it
has reported (its connections' closures hold it: a cycle the collector cannot see)."""

import gc
import threading
import weakref

from dolphinfit.core.errors import InputError
from dolphinfit.ui.workers import background
from dolphinfit.ui.workers.background import BackgroundJobs

TIMEOUT_MS = 20_000   # a loaded machine (load 5 on two cores) took over 5 s


def test_each_jobs_relay_is_freed_once_it_has_reported(qtbot, monkeypatch):
    """This test's own relays, followed by weak references (relays of earlier tests, freed
    or not meanwhile, do not count)."""
    made = []

    class FollowedRelay(background._Relay):
        def __init__(self) -> None:
            super().__init__()
            made.append(weakref.ref(self))

    monkeypatch.setattr(background, "_Relay", FollowedRelay)
    jobs = BackgroundJobs()
    results, errors, threads = [], [], set()

    def fail() -> None:
        raise InputError("no such clip")

    for value in range(20):
        jobs.run(lambda value=value: value,
                 lambda result: (results.append(result), threads.add(threading.current_thread())),
                 errors.append)
    jobs.run(fail, results.append, errors.append)
    qtbot.waitUntil(lambda: len(results) + len(errors) == 21, timeout=TIMEOUT_MS)
    assert results == list(range(20)) and errors == ["no such clip"]
    assert threads == {threading.main_thread()}
    assert len(made) == 21

    def all_freed() -> bool:
        gc.collect()
        return all(relay() is None for relay in made)

    qtbot.waitUntil(all_freed, timeout=TIMEOUT_MS)
