"""Issue 53 §1, a reopened project that crashed 1 time in 4: scipy on the GUI thread met a
torch that the app's background start-up work had half imported; and the failed step left the
results panel on "the clip is still opening"."""

import json
import os
import subprocess
import sys
from pathlib import Path

from PySide6.QtCore import Qt

from .app_waits import results_caught_up
from .test_app import CTRL, SIGNAL_TIMEOUT_MS, measure_by_hand, open_and_wait, press

CHILD = Path(__file__).with_name("import_race_child.py")
CHILD_TIMEOUT_S = 180
HALF_IMPORTED = "partially initialized module 'torch' has no attribute 'Tensor'"


def test_scipy_on_the_gui_thread_never_meets_a_half_imported_torch(tmp_path):
    """A fresh app: stations placed on the GUI thread while torch loads for the start-up work
    do not fail (before the fix, every run failed on its first placement)."""
    env = {**os.environ, "DOLPHINFIT_CONFIG_DIR": str(tmp_path),
           "QT_QPA_PLATFORM": os.environ.get("QT_QPA_PLATFORM", "offscreen")}
    done = subprocess.run([sys.executable, str(CHILD)], env=env, capture_output=True,
                          text=True, timeout=CHILD_TIMEOUT_S)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["error"] is None and report["calls"] >= 1


def test_a_failed_step_on_reopening_leaves_the_results_on_the_measurement(qtbot, new_window,
                                                                          still):
    """The overlay failing once as the reopened clip shows its frame: the error reaches the
    exception hook (the app's crash report), and the results still show the measured frame."""
    window = new_window()
    open_and_wait(qtbot, window, still)
    measure_by_hand(qtbot, window)
    press(qtbot, window, Qt.Key.Key_S, CTRL)
    path = window.model.path
    window.close()

    again = new_window()
    draw = again.overlay.set_frame

    def fails_once(frame_idx):
        again.overlay.set_frame = draw
        raise AttributeError(HALF_IMPORTED)

    again.overlay.set_frame = fails_once
    with qtbot.capture_exceptions() as raised:
        open_and_wait(qtbot, again, path)
    assert [str(error) for _, error, _ in raised] == [HALF_IMPORTED]
    qtbot.waitUntil(lambda: results_caught_up(again), timeout=SIGNAL_TIMEOUT_MS)

