"""A field day's clips in the app, as a user works them: a folder of three clips added in one
step (two dolphins side by side; one dolphin out of view for the first second; a broken SRT),
the broken one reported with its reason, the others scanned in the worker, each animal under
its number with its best frames in the picker, a frame put aside and taken back, the next
clip that needs work, a picked frame measured with suggested edges, fitted and compared."""

import shutil
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
from PySide6.QtCore import Qt

from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.measure.mask_midline import midline_from_mask
from dolphinfit.core.project.fit_settings import FitSettings
from dolphinfit.core.project.scan_store import scan_file
from dolphinfit.core.scan.scan_files import read_scan_json
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.sample import ensure_clip
from dolphinfit.core.project.model import with_animal
from dolphinfit.ui.state.commands import edit_measurement, push_edit
from dolphinfit.ui.state.project_model import Change

SMALL = dict(width_px=480, height_px=270, fps=5.0, duration_s=3.0, altitude_m=9.0,
             heading_deg=10.0, sea_state=0.3)
LAUNCH_HEIGHT_M = 1.5   # the synthetic SRT's rel_alt is the altitude less this
QUICK_FIT = FitSettings(start_s=0.0, end_s=0.4, fps=5.0, quality="quick")


def _late_copy(video: Path, target: Path, blank_s: float) -> None:
    """``video`` with its first ``blank_s`` seconds showing only water (its median colour)."""
    reader = cv2.VideoCapture(str(video))
    fps = reader.get(cv2.CAP_PROP_FPS)
    frames = []
    while True:
        ok, frame = reader.read()
        if not ok:
            break
        frames.append(frame)
    reader.release()
    height, width = frames[0].shape[:2]
    water = np.median(frames[0].reshape(-1, 3), axis=0).astype(np.uint8)
    writer = cv2.VideoWriter(str(target), cv2.VideoWriter_fourcc(*"mp4v"), fps, (width, height))
    for index, frame in enumerate(frames):
        writer.write(np.broadcast_to(water, frame.shape).copy() if index < blank_s * fps
                     else frame)
    writer.release()


@pytest.fixture(scope="module")
def field_day(tmp_path_factory) -> Path:
    """A folder of three clips with their SRTs (module doc)."""
    renders = tmp_path_factory.mktemp("renders")
    pair = ensure_clip(SynthConfig(seed=4, companion_offset_m=1.5, companion_ahead_m=0.6,
                                   **SMALL), renders / "pair")
    one = ensure_clip(SynthConfig(seed=3, **SMALL), renders / "one")
    folder = tmp_path_factory.mktemp("field_day")
    shutil.copy(pair.video, folder / "DJI_0001.mp4")
    shutil.copy(pair.srt, folder / "DJI_0001.SRT")
    _late_copy(one.video, folder / "DJI_0002.mp4", blank_s=1.0)
    shutil.copy(one.srt, folder / "DJI_0002.SRT")
    shutil.copy(one.video, folder / "DJI_0003.mp4")
    (folder / "DJI_0003.SRT").write_text("1\nthe drone's card was full\n", encoding="utf-8")
    return folder


def test_a_field_day_from_folder_to_comparison(qtbot, make_window, field_day):
    window = make_window((1600, 1000))
    reports = []
    window.ask.report = lambda title, text, details: reports.append((text, details))
    window.ask.launch_height = lambda names: LAUNCH_HEIGHT_M
    with qtbot.waitSignal(window.state.session_opened, timeout=60_000):
        window.intake.add([field_day])
    # a project beside the folder; the broken clip reported with its reason, the others added
    project_path = window.model.path
    assert project_path == field_day.parent / f"{field_day.name}.dolphinfit"
    clips = window.model.project.clips
    assert [clip.name for clip in clips] == ["DJI_0001.mp4", "DJI_0002.mp4"]
    assert all(clip.altitude.launch_height_m == LAUNCH_HEIGHT_M for clip in clips)
    text, details = reports[-1]
    assert "2 clips added" in text and "DJI_0003.mp4: " in text and "DJI_0003.SRT" in text
    assert any("no preset at 480×270" in line for line in details)  # the camera to check
    assert "not scanned" in window.project_panel.tree.topLevelItem(0).text(1)

    # every clip scanned in the worker, one after the other; the scans saved with the project
    window.actions_by_name["scan_all"].trigger()
    qtbot.waitUntil(lambda: all(clip.scan_path for clip in window.model.project.clips)
                    and all(window.scans.scan_of(i) for i in range(2)), timeout=120_000)
    pair_scan, late_scan = window.scans.scan_of(0), window.scans.scan_of(1)
    assert pair_scan.animal_ids() == [1, 2]
    assert late_scan.animal_ids() == [1] and late_scan.of_animal(1)[0].frame_idx >= 5
    for clip in window.model.project.clips:
        saved = scan_file(project_path, clip.media_path)
        assert read_scan_json(saved).scores and saved.with_suffix(".csv").is_file()
    assert "2 found · 0 measured" in window.project_panel.tree.topLevelItem(0).text(1)

    # the picker lists the selected clip's animals, best frames first, with pictures
    window.model.select(0)
    picker = window.picker
    qtbot.waitUntil(lambda: picker.animal_box.count() == 2, timeout=10_000)
    best = pair_scan.best(1)
    assert int(picker.table.item(0, 2).data(0)) == best[0].frame_idx
    qtbot.waitUntil(lambda: not picker.table.item(0, 2).icon().isNull(), timeout=30_000)
    # Delete puts the best frame aside (undoable, kept in the project); Delete again takes it
    # back
    picker.table.setFocus()
    picker.table.setCurrentCell(0, 2)
    qtbot.keyClick(picker.table, Qt.Key.Key_Delete)
    assert (1, best[0].frame_idx) in window.model.project.clips[0].rejected_frames
    assert int(picker.table.item(0, 2).data(0)) != best[0].frame_idx
    window.model.undo_stack.undo()
    assert window.model.project.clips[0].rejected_frames == ()

    # Enter measures animal 1 as "dolphin 1" on its best frame
    qtbot.waitUntil(lambda: window.state.session_for(0) is not None, timeout=30_000)
    picker.table.setCurrentCell(0, 2)
    qtbot.keyClick(picker.table, Qt.Key.Key_Return)
    clip = window.model.project.clips[0]
    assert [a.animal_id for a in clip.animals] == ["dolphin 1"]
    assert window.state.frame_idx == best[0].frame_idx
    assert window.model.current_measurement().frame_idx == best[0].frame_idx

    # its masks from a click on the animal: that frame's first, kept while the fit's frames
    # are still being tracked, so its edges can be suggested at once
    animal = window.model.project.clips[0].animals[0]
    push_edit(window.model, with_animal(window.model.project, 0, 0, replace(
        animal, fit_settings=QUICK_FIT)), "a quick fit", Change("structure"))
    kept_while_tracking = []
    window.model.changed.connect(lambda _: kept_while_tracking.append(
        window.masks.tracker.is_running) if window.model.project.clips[0].masks_path
        and not kept_while_tracking else None)
    window.masks.arm_click_seed()
    window.canvas.image_clicked.emit(best[0].centre_x_px, best[0].centre_y_px, None)
    qtbot.waitUntil(lambda: window.model.project.clips[0].masks_path is not None,
                    timeout=60_000)
    assert kept_while_tracking == [True]
    masks = read_masks(project_path.parent / window.model.project.clips[0].masks_path)
    mask = masks.mask(best[0].frame_idx)
    model = window.model
    edit_measurement(model, model.current_key(), replace(
        model.current_measurement(), midline_px=midline_from_mask(mask)), "length")
    window.on_suggest_edges()
    qtbot.waitUntil(lambda: np.isfinite(model.current_measurement().offsets_px).sum() > 30,
                    timeout=30_000)
    qtbot.waitUntil(lambda: not window.masks.tracker.is_running, timeout=120_000)
    fit_frames = window.fits.fit_frames()
    qtbot.waitUntil(lambda: read_masks(project_path.parent / window.model.project.clips[0]
                                       .masks_path).is_visible[fit_frames].all(),
                    timeout=30_000)

    # the fit, and both methods side by side
    with qtbot.waitSignal(window.fits.worker.finished, timeout=300_000):
        window.fits.panel.start_button.click()
    window.docks["Comparison"].raise_()
    qtbot.waitUntil(lambda: window.fits.comparison is not None
                    and window.fits.comparison.table.rowCount() == 5, timeout=60_000)
    assert "fitted" in window.project_panel.tree.topLevelItem(0).text(1)

    # the next clip that needs work: the lone dolphin's, not yet measured
    window.actions_by_name["next_clip"].trigger()
    assert window.model.clip_idx == 1
    assert window.files.save()
