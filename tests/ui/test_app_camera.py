"""Clip → Camera… on several clips at once, from the app: clips selected together in the
Project dock take the camera typed in the real dialog in one undoable step, the dialog's
"every clip of this video size" box sets every clip of the open clip's size, and a camera
typed by its focal length and sensor width is no longer approximate (dialog, project file)."""

import json
from collections.abc import Callable
from pathlib import Path

import cv2
import numpy as np
import pytest
from PySide6.QtCore import Qt, QTimer
from PySide6.QtWidgets import (QAbstractSpinBox, QApplication, QCheckBox, QDialogButtonBox,
                               QLabel)

from dolphinfit.core.project.model import AltitudeSpec, ClipEntry, Project
from dolphinfit.core.project.new_project import default_camera
from dolphinfit.core.project.project_file import write_project
from dolphinfit.ui.dialogs.camera_dialog import CameraDialog

SMALL, LARGE = (320, 240), (640, 480)
SIZES = (SMALL, SMALL, SMALL, LARGE, LARGE)
FOCAL_MM, SENSOR_MM = 8.8, 13.2
FOCAL_PX = FOCAL_MM / SENSOR_MM * SMALL[0]   # 213.33 px
TIMEOUT_MS = 30_000
DIALOG_POLL_MS, DIALOG_POLLS = 50, 200


@pytest.fixture
def survey(tmp_path) -> Path:
    """A saved project of five stills (three 320×240, two 640×480), each with the fallback
    camera (the default preset's lens at its size: approximate) and a 20 m altitude."""
    folder = tmp_path / "survey"
    folder.mkdir()
    clips = []
    for n, size in enumerate(SIZES):
        cv2.imwrite(str(folder / f"DJI_{n}.png"), np.full((size[1], size[0], 3), 90, np.uint8))
        clips.append(ClipEntry(f"DJI_{n}.png", "image", default_camera(*size)[0],
                               altitude=AltitudeSpec(constant_m=20.0, source="manual")))
    path = folder / "survey.dolphinfit"
    write_project(path, Project(clips=tuple(clips)))
    return path


def _open(qtbot, window, path: Path) -> None:
    with qtbot.waitSignal(window.state.session_opened, timeout=TIMEOUT_MS):
        window.files.open_path(path)


def _click_clip(qtbot, window, clip_idx: int, modifier=Qt.KeyboardModifier.NoModifier) -> None:
    """Click a clip's row in the Project dock (Ctrl: add it to the selection); wait until its
    session is open."""
    tree = window.project_panel.tree
    item = tree.topLevelItem(clip_idx)
    qtbot.mouseClick(tree.viewport(), Qt.MouseButton.LeftButton, modifier,
                     tree.visualItemRect(item).center())
    qtbot.waitUntil(lambda: window.state.session is not None
                    and window.state.session.clip_idx == clip_idx, timeout=TIMEOUT_MS)


def _set_camera(qtbot, window, answer: Callable[[CameraDialog], None]) -> list[str]:
    """Clip → Camera…, answered in the real dialog by ``answer`` (which presses OK or not);
    the dialog's readout as shown first and as left."""
    seen, polls = [], [DIALOG_POLLS]

    def attempt() -> None:
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, CameraDialog):
            polls[0] -= 1
            if polls[0] > 0:
                QTimer.singleShot(DIALOG_POLL_MS, attempt)
            return
        derived = dialog.findChild(QLabel, "derived")
        seen.append(derived.text())
        answer(dialog)
        seen.append(derived.text())
        dialog.findChild(QDialogButtonBox).button(QDialogButtonBox.StandardButton.Ok).click()

    QTimer.singleShot(0, attempt)
    window.actions_by_name["camera"].trigger()
    assert seen, "the camera dialog was not shown"
    return seen


def _type_focal_and_sensor(qtbot, dialog: CameraDialog) -> None:
    for name, value in (("focal_mm", FOCAL_MM), ("sensor_width_mm", SENSOR_MM)):
        edit = dialog.findChild(QAbstractSpinBox, name).lineEdit()
        edit.selectAll()
        qtbot.keyClicks(edit, f"{value}")


def _focal_mm(window) -> list[float]:
    return [clip.camera.focal_mm for clip in window.model.project.clips]


def test_selected_clips_take_one_camera_in_one_undoable_step(qtbot, make_window, survey):
    """Three clips selected with Ctrl take the typed camera (not approximate, 213.3 px focal
    length); one Undo gives each its own back; the file holds "approximate": false."""
    window = make_window()
    _open(qtbot, window, survey)
    before = [clip.camera for clip in window.model.project.clips]
    assert all(camera.approximate for camera in before)
    _click_clip(qtbot, window, 0)
    _click_clip(qtbot, window, 1, Qt.KeyboardModifier.ControlModifier)
    _click_clip(qtbot, window, 3, Qt.KeyboardModifier.ControlModifier)
    assert window.project_panel.selected_clips() == [0, 1, 3]
    _click_clip(qtbot, window, 1, Qt.KeyboardModifier.ControlModifier)   # 1 off, 3 open
    _click_clip(qtbot, window, 2, Qt.KeyboardModifier.ControlModifier)
    assert window.project_panel.selected_clips() == [0, 2, 3]
    titles = []
    shown = _set_camera(qtbot, window, lambda dialog: (
        titles.append(dialog.windowTitle()), _type_focal_and_sensor(qtbot, dialog)))
    assert titles == ["Camera and video mode of 3 clips"]
    # the open clip is 2 (320×240): the fallback is approximate, the typed camera is not
    assert "Approximate" in shown[0] and "Approximate" not in shown[1]
    assert "Focal length 213.3 px · GSD 9.37 cm/px at 20 m" in shown[1]
    num_steps = window.model.undo_stack.count()
    qtbot.waitUntil(lambda: window.model.undo_stack.count() == num_steps + 1,
                    timeout=TIMEOUT_MS)
    assert window.model.undo_stack.undoText() == "set camera of 3 clips"
    clips = window.model.project.clips
    assert _focal_mm(window) == [FOCAL_MM, before[1].focal_mm, FOCAL_MM, FOCAL_MM,
                                 before[4].focal_mm]
    assert [clip.camera.approximate for clip in clips] == [False, True, False, False, True]
    assert clips[0].camera.intrinsics().focal_px == pytest.approx(FOCAL_PX)
    assert clips[2].camera.intrinsics().gsd_m_per_px(20.0) == pytest.approx(20.0 / FOCAL_PX)
    # the 640×480 clip took a 320×240 camera: said, not refused
    assert "these clips are not: DJI_3.png" in window.statusBar().currentMessage()

    assert window.files.save()
    saved = [clip["camera"] for clip in json.loads(survey.read_text())["clips"]]
    assert [(c["focal_mm"], c["sensor_width_mm"], c["approximate"]) for c in saved[:3]] == [
        (FOCAL_MM, SENSOR_MM, False), (before[1].focal_mm, before[1].sensor_width_mm, True),
        (FOCAL_MM, SENSOR_MM, False)]

    window.actions_by_name["undo"].trigger()
    assert [clip.camera for clip in window.model.project.clips] == before


def test_every_clip_of_the_video_size_takes_the_camera(qtbot, make_window, survey):
    """With the box ticked on a 640×480 clip, both 640×480 clips take the camera and the
    three 320×240 clips keep theirs; Undo gives both theirs back."""
    window = make_window()
    _open(qtbot, window, survey)
    before = [clip.camera for clip in window.model.project.clips]
    _click_clip(qtbot, window, 4)
    assert window.project_panel.selected_clips() == [4]

    def every_of_size(dialog: CameraDialog) -> None:
        box = dialog.findChild(QCheckBox, "every_clip_of_size")
        assert box.text() == "Use for every clip of this video size (640×480 px)"
        box.setChecked(True)
        _type_focal_and_sensor(qtbot, dialog)

    _set_camera(qtbot, window, every_of_size)
    qtbot.waitUntil(lambda: _focal_mm(window)[3] == FOCAL_MM, timeout=TIMEOUT_MS)
    assert _focal_mm(window) == [before[0].focal_mm] * 3 + [FOCAL_MM] * 2
    assert window.model.undo_stack.undoText() == "set camera of 2 clips"
    assert window.model.project.clips[3].camera.intrinsics().focal_px == pytest.approx(
        FOCAL_MM / SENSOR_MM * LARGE[0])   # 426.7 px
    window.actions_by_name["undo"].trigger()
    assert [clip.camera for clip in window.model.project.clips] == before
