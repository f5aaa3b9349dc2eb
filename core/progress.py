"""Long work's cancel contract: the caller passes a ``threading.Event``; the work checks it
between steps and raises :class:`Cancelled` once it is set, leaving no partial output."""

import threading


class Cancelled(Exception):
    """The caller asked the work to stop."""


def check_cancel(cancel: threading.Event | None) -> None:
    """Raise Cancelled if ``cancel`` is set."""
    if cancel is not None and cancel.is_set():
        raise Cancelled()
