"""The 3D fit from the app on the sample project: a small fit runs in the worker to the end
while the GUI keeps turning, is saved with the project and shown in the 3D viewer; a second
fit cancelled midway keeps its best state as a partial result; the export actions write its
meshes and the comparison CSV; reopening finds the fit, which says it is out of date once
the clip's camera changes (and not after Undo); Start waits for a range with masks.

What the exported files hold is tested without the GUI: tests/core/fit/test_mesh_files.py
(the meshes' bounds) and tests/core/project/test_comparison.py (the CSV's columns and
figures). Here: that the actions reach those writers with the app's fit and project."""

import csv
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from PySide6.QtCore import QRectF, Qt, QTimer

from dolphinfit.core.fit.result_io import read_fit_result
from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.measure.mask_midline import midline_from_mask
from dolphinfit.core.project.fit_settings import FitSettings, fit_dir
from dolphinfit.core.project.mask_store import save_track, with_frame
from dolphinfit.core.project.project_file import relative_media_path
from dolphinfit.core.project.sample import ensure_sample_project
from dolphinfit.ui.dialogs.camera_dialog import CameraAnswer
from dolphinfit.ui.state.commands import edit_measurement
from dolphinfit.ui.main_window import MainWindow

FIT_TIMEOUT_MS = 300_000
SMALL = FitSettings(start_s=0.0, end_s=0.4, fps=5.0, quality="quick")  # 2 frames, quick
LONGER = FitSettings(start_s=0.0, end_s=2.0, fps=5.0, quality="standard")


@pytest.fixture
def sample_copy(tmp_path) -> Path:
    """The sample project saved into a temporary folder (its media stay in the cache)."""
    source = ensure_sample_project()
    return source, tmp_path / "survey.dolphinfit"


def _open(qtbot, window: MainWindow, path: Path) -> None:
    with qtbot.waitSignal(window.state.session_opened, timeout=30_000):
        window.files.open_path(path)


def _measure_from_mask(window: MainWindow, mask: np.ndarray) -> None:
    """Measure the current frame as the README's screenshot does: length and widths from
    the mask (the suggestions a user reviews)."""
    window.on_measure_frame()
    model = window.model
    key = model.current_key()
    edit_measurement(model, key, replace(model.current_measurement(),
                                         midline_px=midline_from_mask(mask)), "length")
    window.overlay.suggest_edges(mask)


def _fit_watched(qtbot, fits, settings: FitSettings):
    """Run a fit from the panel to its end while a 50 ms timer ticks on the GUI thread: the
    worker's outcome, its progress reports, the gaps between ticks from the start and the
    seconds the fit took."""
    ticks, reports = [], []
    timer = QTimer(interval=50)
    timer.timeout.connect(lambda: ticks.append(time.monotonic()))
    fits.worker.progress.connect(reports.append)
    fits.panel.set_settings(settings, 5.0)
    timer.start()
    started = time.monotonic()
    try:
        with qtbot.waitSignal(fits.worker.finished, timeout=FIT_TIMEOUT_MS) as done:
            fits.panel.start_button.click()
            assert fits.panel.cancel_button.isEnabled()
        elapsed = time.monotonic() - started
    finally:
        timer.stop()
    gaps = np.diff([started, *[t for t in ticks if t >= started]])
    return done.args[0], reports, gaps, elapsed


def _fit_cancelled(qtbot, fits, settings: FitSettings):
    """Run a fit from the panel and press Cancel once it optimises ("global"): the worker's
    outcome, the reports that Cancel answered and that began the result stage, and the
    seconds between them."""
    moments, reports = {}, {}

    def cancel_in_global(progress) -> None:
        if progress.stage == "global" and "cancel" not in moments:
            moments["cancel"], reports["cancel"] = time.monotonic(), progress
            fits.panel.cancel_button.click()
        elif progress.stage == "result" and "stopped" not in moments:
            moments["stopped"], reports["stopped"] = time.monotonic(), progress

    fits.panel.set_settings(settings, 5.0)
    fits.worker.progress.connect(cancel_in_global)
    with qtbot.waitSignal(fits.worker.finished, timeout=FIT_TIMEOUT_MS) as cut:
        fits.panel.start_button.click()
    return (cut.args[0], reports["cancel"], reports["stopped"],
            moments["stopped"] - moments["cancel"])


def _export(qtbot, window: MainWindow, action: str, signal: str = "finished") -> None:
    """Trigger File → Export's ``action`` and wait for the export worker's ``signal``."""
    with qtbot.waitSignal(getattr(window.exports.worker, signal), timeout=120_000):
        window.actions_by_name[action].trigger()


def test_fit_runs_saves_shows_and_cancels(qtbot, sample_copy, make_window):
    source, path = sample_copy
    window = make_window()
    try:
        _open(qtbot, window, source)
        assert window.files.save(path)  # Save As into the test folder: the fit goes beside it
        # Save As rebases the altitude file's path: the clip's altitude is read again first
        qtbot.waitUntil(lambda: window.state.session.altitude
                        == window.model.project.clips[0].altitude, timeout=10_000)
        fits = window.fits
        (result, folder), reports, gaps, elapsed = _fit_watched(qtbot, fits, SMALL)
        # the event loop kept turning: a quarter of the 50 ms ticks at least, and no gap over
        # 1 s or, on a loaded machine where the fit itself slows, a quarter of the fit
        assert len(gaps) >= 0.25 * elapsed / 0.05 and gaps.max() < max(1.0, elapsed / 4)
        previews = [r.preview for r in reports if r.preview is not None]
        assert previews and previews[-1].transl.shape == (len(previews[-1].frame_idx), 3)
        steps = [r.step for r in reports]
        assert steps == sorted(steps) and reports[-1].step == reports[-1].total
        # two frames are too few to trust: the fit runs to its end and says so
        assert result.status == "unreliable" and result.finished
        assert result.reasons[0].startswith("only 2 frame(s) fitted")
        animal = window.model.project.clips[0].animals[0]
        expected = fit_dir(path, window.model.project.clips[0].media_path, "dolphin 1")
        assert animal.fit_path == relative_media_path(path.parent, expected)
        assert window.model.is_dirty
        saved = read_fit_result(folder)
        assert saved.volume_m3 == result.volume_m3
        assert f"volume {saved.volume_m3:.4f} m³" in fits.panel.status.text()
        assert "⚠ 3D fit unreliable: only 2 frame(s) fitted" in fits.panel.status.text()

        # the fitted meshes in the format and folder asked for: the fit just shown, 2 frames
        meshes = path.parent / "meshes"
        window.ask.mesh_export = lambda start: (meshes, ".obj")
        _export(qtbot, window, "export_meshes")
        assert window.exports.last_export[0] == meshes / "rest_mesh.obj"
        assert (meshes / "rest_mesh.obj").is_file()
        assert len(list((meshes / "posed").glob("*.obj"))) == len(result.frame_idx) == 2

        # the fitted silhouette is drawn over the frame, where the dolphin's mask is
        qtbot.waitUntil(fits.silhouette.isVisible, timeout=10_000)
        box = fits.silhouette.path().boundingRect()
        clip = window.model.project.clips[0]
        mask = read_masks(path.parent / clip.masks_path).mask(window.state.frame_idx)
        v, u = np.nonzero(mask)
        overlap = box.intersected(QRectF(u.min(), v.min(), np.ptp(u), np.ptp(v)))
        assert overlap.width() * overlap.height() > 0.5 * box.width() * box.height()
        # past the fitted frames 0 and 2 it is hidden, not drawn where the nearest fitted
        # frame had the animal; half way between them it is posed half way
        assert list(result.frame_idx) == [0, 2]
        centres = {}
        for frame in (0, 2, 1):
            for shown, drawn in ((9, False), (frame, True)):
                with qtbot.waitSignal(window.state.frame_shown, timeout=10_000):
                    window.go_to_frame(shown)
                qtbot.waitUntil(lambda: fits.silhouette.isVisible() == drawn, timeout=10_000)
            centre = fits.silhouette.path().boundingRect().center()
            centres[frame] = np.array([centre.x(), centre.y()])
        assert np.linalg.norm(centres[2] - centres[0]) > 2.0   # the animal moved
        np.testing.assert_allclose(centres[1], (centres[0] + centres[2]) / 2, atol=1.0)

        # the 3D viewer holds the fitted mesh and poses it at the frame shown
        # shown with the first fit, the 3D view loads then (not when the app opens)
        qtbot.waitUntil(lambda: fits.viewer is not None, timeout=10_000)
        # its tab joins the results' and the comparison's; the results stay in front
        assert not window.docks["3D view"].isHidden()
        assert window.results.visibleRegion().boundingRect() == window.results.rect()
        if fits.viewer.plotter is not None:
            first = np.array(fits.viewer.fitted_points(), copy=True)
            with qtbot.waitSignal(window.state.frame_shown, timeout=10_000):
                window.go_to_frame(int(result.frame_idx[-1]))
            qtbot.waitUntil(lambda: not np.allclose(first, fits.viewer.fitted_points()),
                            timeout=10_000)
            assert fits.viewer.frame_label == f"fitted frame {int(result.frame_idx[-1])}"

        # a longer fit, cancelled once it optimises: the partial result is kept, labelled
        (partial, _), at_cancel, at_result, stopping_s = _fit_cancelled(qtbot, fits, LONGER)
        # the optimisation stopped (and the result stage began) at once: long before it would
        # have ended, measured by the fit's own pace, not a wall-clock deadline a loaded
        # machine may miss. Under a quarter of the steps left were run (idle: none) and under
        # a quarter of the time they would take by the rate measured at Cancel (idle: ~10 ms)
        steps_left = at_cancel.total - at_cancel.step
        assert at_result.step - at_cancel.step < steps_left / 4
        assert stopping_s < at_cancel.eta_s / 4
        assert partial.status == "cancelled" and "cancelled by the user" in partial.status_message
        assert "partial result" in fits.panel.status.text()
        assert np.isfinite(partial.volume_m3)
        assert window.files.save()

        # the comparison CSV: none before a frame is measured (the error in a dialog), then
        # one row for the animal, from the fit saved last
        window.ask.comparison_path = lambda start: path.with_name("comparison.csv")
        errors = []
        window.ask.warn = lambda title, text: errors.append(text)  # the dialog's words
        _export(qtbot, window, "export_comparison", "failed")
        assert "nothing to compare" in errors[-1]
        assert not path.with_name("comparison.csv").exists()
        masks = read_masks(path.parent / clip.masks_path)
        _measure_from_mask(window, masks.mask(window.state.frame_idx))
        _export(qtbot, window, "export_comparison")
        with path.with_name("comparison.csv").open(newline="", encoding="utf-8") as file:
            rows = list(csv.DictReader(file))
        assert [(row["animal_id"], row["fit_status"]) for row in rows] == [("dolphin 1",
                                                                            "cancelled")]

        # the comparison shows both methods; the fit's HW ratios become the project's table
        window.docks["Comparison"].raise_()  # the panel is built when first shown
        qtbot.waitUntil(lambda: fits.comparison is not None
                        and fits.comparison.table.rowCount() == 5, timeout=60_000)
        volume = fits.comparison.table.item(1, 2).text()  # the fit's, with its interval
        assert volume.startswith(f"{partial.volume_m3:.4f} (") and "–" in volume
        fits.comparison.hw_button.click()
        qtbot.waitUntil(lambda: "_hw_" in window.model.project.hw_ratios, timeout=60_000)
        assert window.model.project.hw_ratios.endswith(".csv")
        qtbot.waitUntil(lambda: window.results.current_result() is not None and
                        window.results.current_result().estimate.settings.hw.name
                        == "3D fit of dolphin 1 (clip.mp4)", timeout=60_000)
        hw = window.results.current_result().record["settings"]["hw_ratios"]
        assert "survey.fits" in hw["source"] and not hw["is_provisional"]
        assert window.files.save()  # else the autosave, 1.5 s after the change, asks on reopening
    finally:
        window.shutdown()

    again = make_window()
    try:
        _open(qtbot, again, path)
        qtbot.waitUntil(lambda: "3D fit cancelled" in again.fits.panel.status.text(),
                        timeout=30_000)
        assert again.model.project.clips[0].animals[0].fit_settings == LONGER
        # the fit keeps what it was made from; a camera changed after it makes it out of date
        assert dict(again.model.project.clips[0].animals[0].fit_inputs).keys() == \
            {"camera", "altitude", "calibration", "lens", "masks"}
        assert "out of date" not in again.fits.panel.status.text()
        camera = again.model.project.clips[0].camera
        again.ask.camera = lambda *args: CameraAnswer(
            replace(camera, focal_mm=camera.focal_mm * 1.1), None)
        again.sessions.set_camera()
        qtbot.waitUntil(lambda: again.fits.panel.status.text().startswith(
            "⚠ out of date: the clip's camera changed since this fit"), timeout=30_000)
        assert "fit again" in again.fits.panel.status.text()
        again.model.undo_stack.undo()
        qtbot.waitUntil(lambda: "out of date" not in again.fits.panel.status.text(),
                        timeout=30_000)
    finally:
        again.shutdown()


def _type(qtbot, box, text: str) -> None:
    """Replace what a spin box shows by typing ``text``, then Enter."""
    box.setFocus()
    box.selectAll()
    qtbot.keyClicks(box, text)
    qtbot.keyClick(box, Qt.Key.Key_Return)


def test_start_waits_for_a_range_with_masks(qtbot, sample_copy, make_window, tmp_path):
    """With no mask on frames 0–24 of the 50: the whole clip fits on the 12 masked frames of
    its 25 (said, Start on); the first 2 s have none (said with what to do, Start off, and a
    start asked for anyway refused); from 3 s on all are masked (nothing said, Start on)."""
    source, path = sample_copy
    window = make_window()
    try:
        _open(qtbot, window, source)
        assert window.files.save(path)
        clip = window.model.project.clips[0]
        truth = read_masks(path.parent / clip.masks_path)
        holed = truth
        for frame_idx in range(25):
            holed = with_frame(holed, frame_idx, np.zeros_like(truth.mask(frame_idx)))
        save_track(holed, tmp_path / "holed.npz")
        fits, panel = window.fits, window.fits.panel
        window.masks.use_masks(0, tmp_path / "holed.npz")
        assert fits.fit_frames() == list(range(0, 50, 2))  # 5 of the clip's 10 frames/s
        qtbot.waitUntil(lambda: panel.mask_note.text().startswith(
            "12 of the 25 frames to fit (frames 0–48) have a usable mask"), timeout=30_000)
        assert panel.start_button.isEnabled()

        _type(qtbot, panel.end_s, "2")  # [0, 2 s): frames 0, 2, …, 18
        hint = ("no usable masks in frames 0–18: track the animal again (Clip → Track the "
                "dolphin from a click, Ctrl+T) or pick another range")
        assert panel.mask_note.text() == f"⚠ {hint}" and panel.mask_note.isVisibleTo(panel)
        assert not panel.start_button.isEnabled()
        fits.start(panel.settings())  # asked for anyway (not by the button): refused, said
        assert not fits.worker.is_running and panel.status.text() == f"⚠ {hint}"

        _type(qtbot, panel.end_s, "5")
        _type(qtbot, panel.start_s, "3")  # frames 30, 32, …, 48: all masked
        assert window.model.project.clips[0].animals[0].fit_settings.start_s == 3.0
        assert not panel.mask_note.isVisibleTo(panel) and panel.start_button.isEnabled()
    finally:
        window.shutdown()
