"""Cycle collection happens on the GUI thread only (ui/gc_guard.py)."""

import gc
import threading


def test_collection_is_off_and_done_by_the_gui_threads_timer(collect_on_the_gui_thread, qtbot):
    assert not gc.isenabled()
    found = []

    class Node:
        def __del__(self):
            found.append(threading.current_thread() is threading.main_thread())

    def more_cycles() -> bool:
        """Cycles only the collector frees, a threshold's worth at a time (the count that
        triggers a collection is allocations less deallocations, and an earlier test's
        objects freed meanwhile lower it)."""
        for _ in range(gc.get_threshold()[0]):
            node = Node()
            node.me = node
        return bool(found)

    qtbot.waitUntil(more_cycles, timeout=10_000)
    assert len(found) >= gc.get_threshold()[0] and all(found)  # on the GUI thread, by the timer
