"""The README's screenshots: the app on the sample project with the dolphin measured, then
with a quick 3D fit beside it (PNG and PNG_fit.png), and the sample clip scanned, its best
frames in the Frames dock (PNG_scan.png).

The measurement is made the way a user would start one: "measure this frame", a length
suggested from the clip's mask (core.measure.mask_midline) and the widths from "suggest edges
from the mask" (the body's, its flippers and flukes left out), one of them selected as a user
reviewing the suggestion would. Then the window waits for
the Monte Carlo intervals and saves itself to a PNG. For the second picture it runs a quick
fit of the first second of the clip from the fit panel, waits for it, and shows the comparison.
The work happens in a copy of the project in a temporary folder; the sample stays as it was.
"""

import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from PySide6.QtCore import QRectF

from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.measure.mask_midline import midline_from_mask
from dolphinfit.core.measure.stations import NUM_STATIONS
from dolphinfit.core.project.fit_settings import FitSettings
from dolphinfit.ui.app import application
from dolphinfit.ui.state.commands import edit_measurement
from dolphinfit.ui.main_window import MainWindow

SCREENSHOT_FRAME = 24     # the sample dolphin lies flat and whole in the frame here
SELECTED_STATION = 6      # 35 %: its handle selected, its label shown
SCREENSHOT_FIT = FitSettings(start_s=2.0, end_s=3.0, fps=5.0, quality="quick")
WINDOW_SIZE = (1900, 1150)
TIMEOUT_S = 600.0
SETTLE_S = 0.5
ZOOM_MARGIN = 0.35        # view this much of the body length around the dolphin


def _wait_until(condition, what: str) -> None:
    app = application()
    deadline = time.monotonic() + TIMEOUT_S
    while not condition():
        if time.monotonic() > deadline:
            raise TimeoutError(f"screenshot: gave up waiting for {what}")
        app.processEvents()
        time.sleep(0.01)


def save_screenshot(project_path: Path, out_png: Path) -> int:
    """Open ``project_path``, measure its first clip's dolphin, save the window to PNG; fit
    it and save the window again to PNG_fit.png."""
    application()
    window = MainWindow(restore_layout=False)
    window.resize(*WINDOW_SIZE)
    window.show()
    window.files.open_path(project_path)
    _wait_until(lambda: window.state.session is not None, "the clip to open")
    with tempfile.TemporaryDirectory() as work:
        if not window.files.save(Path(work) / project_path.name):  # Save As: the fit goes there
            raise OSError(f"{work}: could not save a working copy of the sample project")
        _scan(window, _named(out_png, "scan"))
        _measure_and_fit(window, out_png)
    print(f"wrote {out_png}, {_named(out_png, 'fit')} and {_named(out_png, 'scan')}")
    return 0


def _named(out_png: Path, what: str) -> Path:
    return out_png.with_name(f"{out_png.stem}_{what}{out_png.suffix}")


def _scan(window: MainWindow, out_png: Path) -> None:
    """Scan the sample clip and show its best frames, with their pictures."""
    window.actions_by_name["scan_clip"].trigger()
    picker = window.picker
    _wait_until(lambda: picker.table.rowCount() > 0
                and not picker.table.item(0, 2).icon().isNull(), "the scan's best frames")
    window.docks["Frames"].raise_()
    _grab(window, out_png)


def _grab(window: MainWindow, out_png: Path) -> None:
    settle = time.monotonic() + SETTLE_S  # layouts and renders queued by the last changes
    _wait_until(lambda: time.monotonic() > settle, "the window to settle")
    out_png.parent.mkdir(parents=True, exist_ok=True)
    if not window.grab().save(str(out_png)):
        raise OSError(f"{out_png}: could not write the screenshot")


def _zoom_to_dolphin(window: MainWindow) -> None:
    """Zoom the frame onto the measured dolphin with a margin around it."""
    midline = window.model.current_measurement().midline_px
    low, high = midline.min(axis=0), midline.max(axis=0)
    margin = ZOOM_MARGIN * (high - low).max()
    window.canvas.zoom_to(QRectF(low[0] - margin, low[1] - margin,
                                 high[0] - low[0] + 2 * margin, high[1] - low[1] + 2 * margin))


def _measure_and_fit(window: MainWindow, out_png: Path) -> None:
    window.go_to_frame(SCREENSHOT_FRAME)
    _wait_until(lambda: window.canvas.image_rect().width() > 0, "the frame")
    window.on_measure_frame()
    model = window.model
    clip = model.project.clips[model.clip_idx]
    mask = read_masks(model.path.parent / clip.masks_path).mask(SCREENSHOT_FRAME)
    key = model.current_key()
    edit_measurement(model, key, replace(model.current_measurement(),
                                         midline_px=midline_from_mask(mask)), "suggest length")
    window.on_suggest_edges()
    _wait_until(lambda: np.isfinite(model.current_measurement().offsets_px).all(axis=1).sum()
                >= NUM_STATIONS - 1, "the suggested edges")
    while window.overlay.selected_edge != (SELECTED_STATION, 0):
        window.overlay.next_handle()
    _zoom_to_dolphin(window)
    _wait_until(lambda: window.results.current_result() is not None
                and window.results.current_result().estimate.interval is not None,
                "the Monte Carlo intervals")
    _grab(window, out_png)
    fits = window.fits
    fits.panel.set_settings(SCREENSHOT_FIT, window.state.session.source.clip.duration_s)
    fits.panel.start_button.click()
    _wait_until(lambda: not fits.worker.is_running, "the 3D fit")
    window.docks["Comparison"].raise_()
    window.docks["3D fit"].raise_()
    _wait_until(lambda: fits.comparison is not None and fits.comparison.table.rowCount() > 0,
                "the comparison")
    _wait_until(fits.silhouette.isVisible, "the fitted silhouette")
    _wait_until(lambda: fits.viewer is not None, "the 3D view")
    _zoom_to_dolphin(window)
    _grab(window, _named(out_png, "fit"))
    window.model.mark_saved()  # nothing of the demonstration is kept
    window.close()
