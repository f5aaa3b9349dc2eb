"""Cyclic garbage collection on the GUI thread only.

Python's cycle collector runs in whichever thread happens to allocate when a threshold is
crossed. When that is a worker thread (results, exports, decoding), Qt objects in the collected
cycles are destroyed there; an active timer destroyed off its thread leaves a dangling entry
in the GUI thread's timer list, and the event loop crashes on it later. So the app switches
automatic collection off and collects from a timer on the GUI thread, a generation at a time
as the counts pass the usual thresholds (the scheme calibre uses for the same reason).
"""

import gc

from PySide6.QtCore import QObject, QTimer

CHECK_INTERVAL_MS = 500


class GuiThreadGarbageCollector(QObject):
    """Owns the collection for the process while it lives; ``stop()`` hands it back."""

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self._thresholds = gc.get_threshold()
        gc.disable()
        self._timer = QTimer(self, interval=CHECK_INTERVAL_MS)
        self._timer.timeout.connect(self.check)
        self._timer.start()

    def check(self) -> None:
        """Collect the oldest generation whose count has passed its threshold."""
        counts = gc.get_count()
        if counts[0] <= self._thresholds[0]:
            return
        generation = 0
        for level in (1, 2):
            if counts[level] > self._thresholds[level]:
                generation = level
        gc.collect(generation)

    def stop(self) -> None:
        """Back to Python's automatic collection."""
        self._timer.stop()
        gc.enable()
