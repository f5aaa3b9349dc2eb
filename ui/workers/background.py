"""One-shot background jobs (opening media, reading telemetry, saving) on Qt's thread pool,
with the result or the error delivered to the GUI thread by signal."""

import logging
from collections.abc import Callable
from typing import Any

from PySide6.QtCore import QObject, QRunnable, QThreadPool, Signal

from dolphinfit.core.errors import InputError
from dolphinfit.core.progress import Cancelled

log = logging.getLogger(__name__)


def guarded(fn: Callable[[], Any]) -> tuple[bool, Any]:
    """Call ``fn`` off the GUI thread: (True, its result), or (False, the message the user
    reads) for bad input, OS errors and internal errors (logged). A core.progress.Cancelled
    passes through, for the caller to report as such."""
    try:
        return True, fn()
    except Cancelled:
        raise
    except (InputError, ValueError, OSError) as exc:
        return False, str(exc)
    except Exception as exc:  # an internal error still reaches the user, as a message
        log.exception("background job failed")
        return False, f"internal error: {exc!r}"


class _Relay(QObject):
    done = Signal(object)
    failed = Signal(str)


class _Job(QRunnable):
    def __init__(self, fn: Callable[[], Any], relay: _Relay) -> None:
        super().__init__()
        self._fn = fn
        self._relay = relay

    def run(self) -> None:
        fn, relay = self._fn, self._relay
        self._fn = self._relay = None   # the pool may keep the runnable a while: it holds nothing
        try:
            ok, value = guarded(fn)
        except Cancelled as exc:  # one-shot jobs take no cancel: an internal error if raised
            ok, value = False, f"internal error: {exc!r}"
        (relay.done if ok else relay.failed).emit(value)


class BackgroundJobs(QObject):
    """Runs callables off the GUI thread; keeps each relay alive until it has reported, then
    deletes it: its connections hold the closures that hold it, a cycle the collector
    cannot see, so it would otherwise live as long as the process."""

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self._pool = QThreadPool(self)
        self._pool.setMaxThreadCount(1)  # jobs run in order: a save never overtakes an edit
        self._relays: set[_Relay] = set()

    def run(self, fn: Callable[[], Any], on_done: Callable[[Any], None],
            on_failed: Callable[[str], None]) -> None:
        """Call ``fn()`` in the pool; then ``on_done(result)`` or ``on_failed(message)``."""
        relay = _Relay()
        self._relays.add(relay)

        def finish(handler: Callable[[Any], None], value: Any) -> None:
            self._relays.discard(relay)
            relay.deleteLater()
            handler(value)

        relay.done.connect(lambda value: finish(on_done, value))
        relay.failed.connect(lambda message: finish(on_failed, message))
        self._pool.start(_Job(fn, relay))

    def wait(self, timeout_ms: int = 10_000) -> bool:
        """Block until every job has finished (closing the window)."""
        return self._pool.waitForDone(timeout_ms)
