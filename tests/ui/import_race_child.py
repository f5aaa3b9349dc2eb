"""The start of the real app in a fresh interpreter (torch not yet imported), for
tests/ui/test_import_race.py: the window's start-up work runs in the background while the GUI
thread places stations (a scipy call, as the overlay's redraw does on a reopened project),
from the moment torch is in ``sys.modules`` until it is whole. Prints one JSON line: the
error the GUI thread met (null for none) and how many placements it made.

  python import_race_child.py
"""

import json
import sys
import time

import numpy as np

WAIT_S = 60.0
CLICKS_PX = np.array([[100.0, 200.0], [300.0, 190.0], [500.0, 210.0]])


def main() -> int:
    from dolphinfit.core.measure.annotation import place_stations
    from dolphinfit.ui.app import application
    from dolphinfit.ui.main_window import MainWindow

    application()
    window = MainWindow(restore_layout=False)   # asks torch about CUDA in the background
    deadline = time.monotonic() + WAIT_S
    while "torch" not in sys.modules and time.monotonic() < deadline:
        time.sleep(0.0005)
    torch = sys.modules["torch"]
    error, calls = None, 0
    while error is None and time.monotonic() < deadline:
        whole = hasattr(torch, "Tensor")   # from here on no placement can meet half a torch
        try:
            place_stations(CLICKS_PX)
        except AttributeError as exc:
            error = repr(exc)
        calls += 1
        if whole:
            break
    window.shutdown()
    print(json.dumps({"error": error, "calls": calls}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
