"""Masks in the app on the sample project: the tracker seeded by a click on the dolphin,
its masks kept beside the project and shown as an outline and a coverage strip, a frame
corrected with the brush, the switch of masks undone, and edges suggested from a mask."""

import threading
from dataclasses import replace

import numpy as np
import pytest
from PySide6.QtCore import QPointF, Qt

from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.progress import Progress
from dolphinfit.core.measure.mask_midline import midline_from_mask
from dolphinfit.core.project.mask_store import masks_file, save_track, with_frame
from dolphinfit.core.project.model import with_animal
from dolphinfit.core.project.project_file import relative_media_path
from dolphinfit.core.project.sample import ensure_sample_project
from dolphinfit.core.segment.segmenter import FrameTracked
from dolphinfit.ui.main_window import MainWindow
from dolphinfit.ui.state.commands import edit_measurement, push_edit
from dolphinfit.ui.state.project_model import Change
from dolphinfit.ui.widgets.overlay_items import HandleItem
from dolphinfit.ui.workers.tracker_jobs import Tracked

TIMEOUT_MS = 120_000
LEFT = Qt.MouseButton.LeftButton


@pytest.fixture
def window(qtbot, tmp_path, make_window) -> MainWindow:
    window = make_window()
    with qtbot.waitSignal(window.state.session_opened, timeout=30_000):
        window.files.open_path(ensure_sample_project())
    assert window.files.save(tmp_path / "survey.dolphinfit")
    return window


def _kept(window: MainWindow) -> str:
    """Where the open clip's tracked or imported masks are kept, relative to the project."""
    path = window.model.path
    return relative_media_path(path.parent,
                               masks_file(path, window.model.project.clips[0].media_path))


def _iou(a: np.ndarray, b: np.ndarray) -> float:
    return float((a & b).sum() / (a | b).sum())


def test_track_every_frame_asks_the_tracker_for_all_of_them(qtbot, window, monkeypatch):
    """Clip → Track every frame re-tracks from the frame's mask with no limit to the fit's
    frames (the network otherwise sees only those)."""
    from dolphinfit.ui.controllers import mask_controller
    asked = []

    def track_job(*args, **kwargs):
        asked.append(args)
        return lambda progress, cancel: Tracked(window.masks.track, 1)
    monkeypatch.setattr(mask_controller, "track_job", track_job)
    qtbot.waitUntil(lambda: window.masks.track is not None, timeout=10_000)
    with qtbot.waitSignal(window.state.frame_shown, timeout=10_000):
        window.go_to_frame(20)
    with qtbot.waitSignal(window.masks.tracking_done, timeout=10_000):
        window.masks.retrack_here()
    assert asked[0][2] == 20 and asked[0][-1] == window.fits.fit_frames()
    with qtbot.waitSignal(window.masks.tracking_done, timeout=10_000):
        window.actions_by_name["track_every_frame"].trigger()
    assert asked[1][2] == 20 and asked[1][-1] is None


def test_the_coverage_strip_fills_as_frames_are_tracked(qtbot, window, monkeypatch):
    """Each frame a running tracker reports shows on the coverage strip at once: a frame
    found lost turns lost before the run ends."""
    from dolphinfit.ui.controllers import mask_controller
    qtbot.waitUntil(lambda: window.masks.track is not None, timeout=10_000)
    qtbot.waitUntil(lambda: window.masks._coverage is not None, timeout=10_000)
    assert window.masks._coverage.visible[21]
    shown = []
    window.masks.coverage_changed.connect(lambda c: shown.append(c))

    def track_job(*args, **kwargs):
        def job(progress, cancel):
            for step, (frame_idx, seen) in enumerate(((20, True), (21, False)), start=1):
                progress(Progress("track", step, 2, preview=FrameTracked(frame_idx, seen,
                                                                         False)))
            return Tracked(window.masks.track, 2)
        return job
    monkeypatch.setattr(mask_controller, "track_job", track_job)
    with qtbot.waitSignal(window.state.frame_shown, timeout=10_000):
        window.go_to_frame(20)
    with qtbot.waitSignal(window.masks.tracking_done, timeout=10_000):
        window.masks.retrack_here()
    assert shown and not shown[-1].visible[21] and shown[-1].visible[20]
    assert shown[-1].visible.sum() == window.masks.track.is_visible.sum() - 1


def test_track_from_a_click_then_correct_with_the_brush(qtbot, window):
    truth = read_masks(window.model.path.parent / window.model.project.clips[0].masks_path)
    # the sample's dolphin fitted at 2 frames/s: the network tracks 10 of the 50 frames
    animal = window.model.project.clips[0].animals[0]
    push_edit(window.model, with_animal(window.model.project, 0, 0, replace(
        animal, fit_settings=replace(animal.fit_settings, fps=2.0))),
        "fit at 2 frames/s", Change("structure"))
    window.model.select(0, 0)
    with qtbot.waitSignal(window.state.frame_shown, timeout=10_000):
        window.go_to_frame(20)
    v, u = np.nonzero(truth.mask(20))
    qtbot.waitUntil(lambda: window.masks.track is not None, timeout=10_000)  # the clip's masks
    window.canvas.setFocus()
    qtbot.keyClick(window.canvas, Qt.Key.Key_T, Qt.KeyboardModifier.ControlModifier)
    with qtbot.waitSignal(window.masks.tracking_done, timeout=TIMEOUT_MS) as tracked:
        qtbot.mouseClick(window.canvas.viewport(), LEFT,
                         pos=window.canvas.mapFromScene(QPointF(u.mean(), v.mean())))
    track = tracked.args[0].track
    assert window.model.current_measurement() is None  # the click seeded, measured nothing
    qtbot.waitUntil(lambda: window.model.project.clips[0].masks_path == _kept(window),
                    timeout=10_000)
    fit_frames = window.fits.fit_frames()
    assert len(fit_frames) == 10 and 20 in fit_frames and 49 not in fit_frames
    for frame in fit_frames:  # the network tracked only the frames the fit uses
        assert _iou(track.mask(frame), truth.mask(frame)) > 0.7
    assert np.array_equal(track.mask(49), truth.mask(49))  # the others keep their masks
    # the frame's outline is drawn around the tracked mask
    qtbot.waitUntil(lambda: not window.masks.layer.outline_path().isEmpty(), timeout=10_000)
    box = window.masks.layer.outline_path().boundingRect()
    assert box.contains(QPointF(u.mean(), v.mean()))

    # correct frame 20 with the brush: a stroke over open water joins the mask
    window.canvas.setFocus()
    qtbot.keyClick(window.canvas, Qt.Key.Key_B)
    assert window.masks.layer.tool == "brush"
    qtbot.waitUntil(lambda: window.masks.layer.editing_frame == 20, timeout=10_000)
    start, end = (QPointF(60.0, 60.0), QPointF(90.0, 60.0))
    viewport = window.canvas.viewport()
    with qtbot.waitSignal(window.masks.layer.mask_edited, timeout=10_000):
        qtbot.mousePress(viewport, LEFT, pos=window.canvas.mapFromScene(start))
        for x in np.linspace(60.0, 90.0, 8):
            qtbot.mouseMove(viewport, pos=window.canvas.mapFromScene(QPointF(x, 60.0)))
        qtbot.mouseRelease(viewport, LEFT, pos=window.canvas.mapFromScene(end))
    saved = window.model.path.parent / _kept(window)
    qtbot.waitUntil(lambda: read_masks(saved).mask(20)[60, 75], timeout=10_000)
    assert not read_masks(saved).mask(21)[60, 75]  # only the corrected frame changed

    # undo the switch to the tracked masks: the clip reads its old masks again
    window.masks.set_tool(None)
    window.model.undo_stack.undo()
    assert window.model.project.clips[0].masks_path.endswith("masks")
    qtbot.waitUntil(lambda: window.masks.track is not None
                    and window.masks.track.num_frames == truth.num_frames, timeout=10_000)


def test_imported_masks_are_kept_with_the_project(qtbot, window):
    clip = window.model.project.clips[0]
    source = (window.model.path.parent / clip.masks_path).resolve()  # the sample's PNG folder
    window.masks.use_masks(0, source)
    qtbot.waitUntil(lambda: window.model.project.clips[0].masks_path == _kept(window),
                    timeout=30_000)
    kept, original = read_masks(window.model.path.parent / _kept(window)), read_masks(source)
    np.testing.assert_array_equal(kept.stack(), original.stack())
    window.model.undo_stack.undo()
    assert window.model.project.clips[0].masks_path == clip.masks_path


def _truth(window: MainWindow):
    """The sample clip's own masks (a PNG folder)."""
    return read_masks(window.model.path.parent / window.model.project.clips[0].masks_path)


def test_the_clicked_frames_mask_is_drawn_once_that_frame_is_tracked(qtbot, window, tmp_path,
                                                                     monkeypatch):
    """A click on a frame with no mask tracks that frame first: its outline is drawn as soon
    as that run ends, while the fit's frames are still being tracked, with no frame change."""
    from dolphinfit.ui.controllers import mask_controller
    truth = _truth(window)
    with qtbot.waitSignal(window.state.frame_shown, timeout=10_000):
        window.go_to_frame(20)
    holed = tmp_path / "holed.npz"  # the sample's masks, none on frame 20
    save_track(with_frame(truth, 20, np.zeros_like(truth.mask(20))), holed)
    window.masks.use_masks(0, holed)
    qtbot.waitUntil(lambda: window.masks.track is not None
                    and not window.masks.track.is_visible[20], timeout=30_000)
    assert window.masks.layer.outline_path().isEmpty()
    released, asked = threading.Event(), []

    def track_job(media, seed, start_frame, direction, track, backend, checkpoint, only,
                  device):
        asked.append(only)

        def job(progress, cancel):
            if only != [20]:  # the fit's frames: still tracking while the test looks
                released.wait(30)
            return Tracked(truth, len(only))
        return job
    monkeypatch.setattr(mask_controller, "track_job", track_job)
    seeks = []
    window.state.frame_shown.connect(seeks.append)
    v, u = np.nonzero(truth.mask(20))
    try:
        window.masks.arm_click_seed()
        qtbot.mouseClick(window.canvas.viewport(), LEFT,
                         pos=window.canvas.mapFromScene(QPointF(u.mean(), v.mean())))
        qtbot.waitUntil(lambda: not window.masks.layer.outline_path().isEmpty(),
                        timeout=10_000)
        assert asked[0] == [20] and len(asked) == 2 and window.masks.tracker.is_running
    finally:
        with qtbot.waitSignal(window.masks.tracking_done, timeout=10_000):
            released.set()
    box = window.masks.layer.outline_path().boundingRect()
    # the outline runs along the mask's edge pixels: its box is the mask's, within a pixel
    np.testing.assert_allclose([box.left(), box.top(), box.right(), box.bottom()],
                               [u.min(), v.min(), u.max(), v.max()], atol=1.0)
    assert seeks == [] and window.state.frame_idx == 20


def test_suggested_edges_are_shown_at_once(qtbot, window):
    """Suggest edges switches to widths mode (W), where the edges are drawn: every suggested
    edge's handle is on show without a key."""
    truth = _truth(window)
    with qtbot.waitSignal(window.state.frame_shown, timeout=10_000):
        window.go_to_frame(20)
    window.on_measure_frame()
    model = window.model
    edit_measurement(model, model.current_key(), replace(
        model.current_measurement(), midline_px=midline_from_mask(truth.mask(20))), "length")

    def edge_handles() -> list:
        return [item for item in window.canvas.scene().items()
                if isinstance(item, HandleItem) and item.tag[0] == "edge" and item.isVisible()]
    assert window.overlay.mode == "length" and edge_handles() == []
    window.actions_by_name["suggest_edges"].trigger()
    qtbot.waitUntil(lambda: np.isfinite(model.current_measurement().offsets_px).sum() > 30,
                    timeout=30_000)
    num_placed = int(np.isfinite(model.current_measurement().offsets_px).sum())
    assert window.overlay.mode == "widths" and window.actions_by_name["widths_mode"].isChecked()
    assert len(edge_handles()) == num_placed
