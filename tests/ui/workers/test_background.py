"""Background jobs deliver each outcome on the GUI thread and free each job's relay once it
has reported (its connections' closures hold it: a cycle the collector cannot see)."""

import gc
import threading

from dolphinfit.core.errors import InputError
from dolphinfit.ui.workers.background import BackgroundJobs, _Relay

TIMEOUT_MS = 5000


def live_relays() -> int:
    gc.collect()
    return sum(type(thing) is _Relay for thing in gc.get_objects())


def test_each_jobs_relay_is_freed_once_it_has_reported(qtbot):
    jobs = BackgroundJobs()
    before = live_relays()
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
    qtbot.waitUntil(lambda: live_relays() == before, timeout=TIMEOUT_MS)
