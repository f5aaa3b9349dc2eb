"""Cycle collection happens on the GUI thread only (ui/gc_guard.py)."""

import gc
import threading


def test_collection_is_off_and_done_by_the_gui_threads_timer(collect_on_the_gui_thread, qtbot):
    assert not gc.isenabled()
    found = []

    class Node:
        def __del__(self):
            found.append(threading.current_thread() is threading.main_thread())

    for _ in range(gc.get_threshold()[0] + 50):
        node = Node()
        node.me = node  # a cycle only the collector frees
    del node
    qtbot.waitUntil(lambda: len(found) > gc.get_threshold()[0], timeout=5000)
    assert all(found)  # freed by the timer, on the GUI thread
