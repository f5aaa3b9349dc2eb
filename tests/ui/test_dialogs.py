"""The app's dialogs, driven through their widgets: altitude, camera, relink, shortcuts,
animal and handle style."""

import json
import shutil
from pathlib import Path

import pytest
from PySide6.QtCore import Qt
from PySide6.QtGui import QColor, QKeySequence
from PySide6.QtWidgets import (QAbstractSpinBox, QColorDialog, QComboBox, QDialog,
                               QDialogButtonBox, QFileDialog, QInputDialog, QLabel, QLineEdit,
                               QListWidget, QPlainTextEdit, QPushButton, QRadioButton,
                               QTableWidget, QWidget)

from dolphinfit.core.camera_presets import load_presets
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.video import Clip
from dolphinfit.core.project.model import AltitudeSpec
from dolphinfit.ui.action_table import load_action_table
from dolphinfit.ui.dialogs.altitude_dialog import AltitudeDialog
from dolphinfit.ui.dialogs.animal_dialog import AnimalDialog
from dolphinfit.ui.dialogs.camera_dialog import CameraDialog
from dolphinfit.ui.dialogs.handle_style_dialog import HandleStyleDialog
from dolphinfit.ui.dialogs.launch_height_dialog import LaunchHeightDialog
from dolphinfit.ui.state.handle_style import HandleStyle
from dolphinfit.ui.dialogs.relink_dialog import RelinkDialog
from dolphinfit.ui.action_table import MOUSE_GESTURES
from dolphinfit.ui.dialogs.shortcuts_dialog import ShortcutsDialog

DATA = Path(__file__).parents[1] / "data"
SRT_SAMPLE = DATA / "srt" / "p4p_sample.SRT"  # single-line family: H, relative, 45.60 m
LASER_LOG = DATA / "laser" / "LOG_0007.CSV"
FPS, NUM_FRAMES = 30.0, 300
PRESET_5K, PRESET_FHD = "dji-mavic3-5.1k", "dji-mavic3-fhd"


def show(qtbot, dialog: QDialog) -> QDialog:
    qtbot.addWidget(dialog)
    dialog.show()
    qtbot.waitExposed(dialog)
    return dialog


def child(dialog: QWidget, kind: type, name: str) -> QWidget:
    widget = dialog.findChild(kind, name)
    assert widget is not None, name
    return widget


def ok_button(dialog: QDialog) -> QPushButton:
    return dialog.findChild(QDialogButtonBox).button(QDialogButtonBox.StandardButton.Ok)


def type_into(qtbot, widget: QLineEdit | QAbstractSpinBox, text: str) -> None:
    """Replace a line edit's or spin box's text by typing ``text``."""
    edit = widget.lineEdit() if isinstance(widget, QAbstractSpinBox) else widget
    edit.selectAll()
    qtbot.keyClicks(edit, text)


def box_button(dialog: QDialog, text: str) -> QPushButton:
    return next(b for b in dialog.findChild(QDialogButtonBox).buttons() if b.text() == text)


def click(qtbot, button: QPushButton | QRadioButton) -> None:
    qtbot.mouseClick(button, Qt.MouseButton.LeftButton)


def fake_clip(path: Path, num_frames: int = NUM_FRAMES) -> Clip:
    return Clip(path=path, fps=FPS, num_frames=num_frames, width_px=1920, height_px=1080)


# --------------------------------------------------------------------------------------------
# Altitude


@pytest.fixture
def media_dir(tmp_path: Path) -> Path:
    folder = tmp_path / "media"
    folder.mkdir()
    return folder


def test_altitude_preselects_the_sidecar_and_needs_a_launch_height(qtbot, tmp_path, media_dir):
    shutil.copy(SRT_SAMPLE, media_dir / "DJI_0042.SRT")
    clip_path = media_dir / "DJI_0042.MP4"
    dialog = show(qtbot, AltitudeDialog(clip_path, tmp_path, fake_clip(clip_path)))
    sidecar = child(dialog, QRadioButton, "sidecar")
    launch = child(dialog, QLineEdit, "launch_height_m")
    assert sidecar.isChecked() and "DJI_0042.SRT" in sidecar.text()
    assert child(dialog, QComboBox, "source").currentText() == "barometer"
    assert launch.isEnabled() and not child(dialog, QAbstractSpinBox, "time_offset_s").isEnabled()
    error = child(dialog, QLabel, "error")
    assert error.isVisible() and "launch height" in error.text()
    assert not ok_button(dialog).isEnabled()
    with pytest.raises(InputError, match="launch height"):
        dialog.spec

    type_into(qtbot, launch, "1.5")
    assert ok_button(dialog).isEnabled() and not error.isVisible()
    preview = child(dialog, QLabel, "preview").text()
    assert "5 samples, 5 valid, 1 Hz" in preview and "47.10–47.10 m" in preview
    click(qtbot, ok_button(dialog))
    assert dialog.result() == QDialog.DialogCode.Accepted
    assert dialog.spec == AltitudeSpec(path="media/DJI_0042.SRT", launch_height_m=1.5,
                                       source="barometer")


def test_altitude_constant_is_manual(qtbot, tmp_path, media_dir):
    clip_path = media_dir / "DJI_0043.MP4"
    dialog = show(qtbot, AltitudeDialog(clip_path, tmp_path, fake_clip(clip_path)))
    assert not child(dialog, QRadioButton, "sidecar").isEnabled()
    assert child(dialog, QRadioButton, "file").isChecked()  # a video without sidecar
    assert not ok_button(dialog).isEnabled()

    click(qtbot, child(dialog, QRadioButton, "constant"))
    type_into(qtbot, child(dialog, QAbstractSpinBox, "constant_m"), "18.5")
    assert not child(dialog, QLineEdit, "launch_height_m").isEnabled()
    assert "18.50 m" in child(dialog, QLabel, "preview").text()
    click(qtbot, ok_button(dialog))
    assert dialog.spec == AltitudeSpec(constant_m=18.5, source="manual")


def test_altitude_of_a_still_preselects_the_constant(qtbot, tmp_path, media_dir):
    image = media_dir / "DJI_0044.JPG"
    dialog = show(qtbot, AltitudeDialog(image, tmp_path, fake_clip(image, num_frames=1)))
    assert child(dialog, QRadioButton, "constant").isChecked()
    assert ok_button(dialog).isEnabled()
    assert dialog.spec.source == "manual"


def test_altitude_broken_csv_shows_the_error_and_disables_ok(qtbot, tmp_path, media_dir,
                                                            monkeypatch):
    broken = media_dir / "altitude.csv"
    broken.write_text("frame,altitude_m\n0,abc\n")
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *args: (str(broken), ""))
    clip_path = media_dir / "DJI_0045.MP4"
    dialog = show(qtbot, AltitudeDialog(clip_path, tmp_path, fake_clip(clip_path),
                                        AltitudeSpec(constant_m=20.0)))
    assert ok_button(dialog).isEnabled()
    click(qtbot, child(dialog, QPushButton, "browse"))
    preview = child(dialog, QLabel, "preview")
    assert child(dialog, QRadioButton, "file").isChecked()
    assert "altitude.csv, line 2" in preview.text()
    assert "#d32f2f" in preview.styleSheet()
    assert not ok_button(dialog).isEnabled()
    with pytest.raises(InputError, match="not a number"):
        dialog.spec


def test_altitude_laser_log_takes_a_time_offset(qtbot, tmp_path, media_dir, monkeypatch):
    log = shutil.copy(LASER_LOG, media_dir / "LOG_0007.CSV")
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *args: (str(log), ""))
    clip_path = media_dir / "DJI_0046.MP4"
    dialog = show(qtbot, AltitudeDialog(clip_path, tmp_path, fake_clip(clip_path)))
    click(qtbot, child(dialog, QPushButton, "browse"))
    offset = child(dialog, QAbstractSpinBox, "time_offset_s")
    assert offset.isEnabled() and not child(dialog, QLineEdit, "launch_height_m").isEnabled()
    assert child(dialog, QComboBox, "source").currentText() == "laser"
    type_into(qtbot, offset, "2.5")
    click(qtbot, ok_button(dialog))
    assert dialog.spec == AltitudeSpec(path="media/LOG_0007.CSV", time_offset_s=2.5,
                                       source="laser")


def test_altitude_shows_the_current_spec(qtbot, tmp_path, media_dir):
    shutil.copy(SRT_SAMPLE, media_dir / "DJI_0047.SRT")
    clip_path = media_dir / "DJI_0047.MP4"
    current = AltitudeSpec(path="media/DJI_0047.SRT", launch_height_m=2.0, source="manual")
    dialog = show(qtbot, AltitudeDialog(clip_path, tmp_path, fake_clip(clip_path), current))
    assert child(dialog, QRadioButton, "sidecar").isChecked()
    assert child(dialog, QComboBox, "source").currentText() == "manual"
    assert dialog.spec == current


# --------------------------------------------------------------------------------------------
# Camera


def spin_values(dialog: CameraDialog) -> tuple[float, ...]:
    return tuple(child(dialog, QAbstractSpinBox, name).value() for name in
                 ("focal_mm", "sensor_width_mm", "image_width_px", "image_height_px"))


def choose_preset(dialog: CameraDialog, name: str) -> None:
    combo = child(dialog, QComboBox, "preset")
    combo.setCurrentIndex(combo.findData(name))


def test_camera_preset_fills_the_fields_and_editing_makes_it_own_values(qtbot):
    presets = load_presets()
    dialog = show(qtbot, CameraDialog(presets[PRESET_FHD], PRESET_FHD, 5120, 2700))
    assert "(approximate)" in child(dialog, QComboBox, "preset").currentText()
    choose_preset(dialog, PRESET_5K)
    assert spin_values(dialog) == (12.29, 17.27, 5120, 2700)
    assert dialog.preset_name == PRESET_5K and dialog.camera == presets[PRESET_5K]
    derived = child(dialog, QLabel, "derived")
    assert "Focal length 3643.6 px" in derived.text()  # 12.29 / 17.27 × 5120
    assert "GSD 0.55 cm/px at 20 m" in derived.text()
    assert not child(dialog, QLabel, "mismatch").isVisible()

    type_into(qtbot, child(dialog, QAbstractSpinBox, "focal_mm"), "24")
    assert dialog.preset_name is None
    assert child(dialog, QComboBox, "preset").currentIndex() == -1
    assert dialog.camera.focal_mm == 24.0 and dialog.camera.sensor_width_mm == 17.27
    assert "Focal length 7115.2 px" in derived.text()  # 24 / 17.27 × 5120


def test_camera_mismatch_warning_and_use_the_clip_size(qtbot):
    dialog = show(qtbot, CameraDialog(load_presets()[PRESET_5K], PRESET_5K, 1280, 720))
    warning = child(dialog, QLabel, "mismatch")
    use_clip_size = child(dialog, QPushButton, "use_clip_size")
    assert warning.isVisible() and "5120×2700" in warning.text() and use_clip_size.isVisible()
    click(qtbot, use_clip_size)
    assert not warning.isVisible() and not use_clip_size.isVisible()
    assert spin_values(dialog)[2:] == (1280, 720)
    assert dialog.preset_name is None
    assert (dialog.camera.image_width_px, dialog.camera.image_height_px) == (1280, 720)


def test_camera_save_as_my_preset(qtbot, monkeypatch, config_dir):
    monkeypatch.setattr(QInputDialog, "getText", lambda *args, **kwargs: (" my drone ", True))
    dialog = show(qtbot, CameraDialog(load_presets()[PRESET_5K], PRESET_5K, 5120, 2700))
    type_into(qtbot, child(dialog, QAbstractSpinBox, "focal_mm"), "12.5")
    click(qtbot, child(dialog, QPushButton, "save_preset"))
    saved = json.loads((config_dir / "cameras.json").read_text())["presets"]
    assert [(p["name"], p["focal_mm"], p["image_width_px"]) for p in saved] == [
        ("my drone", 12.5, 5120)]
    assert dialog.preset_name == "my drone" and dialog.camera.focal_mm == 12.5
    assert child(dialog, QComboBox, "preset").currentData() == "my drone"
    assert load_presets()["my drone"] == dialog.camera


# --------------------------------------------------------------------------------------------
# Relink, shortcuts, animal, handle style


def test_relink_returns_the_selected_candidate(qtbot, tmp_path):
    candidates = [tmp_path / "a" / "DJI_0042.MP4", tmp_path / "b" / "DJI_0042.MP4"]
    dialog = show(qtbot, RelinkDialog("clips/DJI_0042.MP4", tmp_path, candidates))
    assert "DJI_0042.MP4 was not found at" in dialog.findChild(QLabel).text()
    listing = child(dialog, QListWidget, "candidates")
    assert listing.currentRow() == 0
    listing.setCurrentRow(1)
    click(qtbot, box_button(dialog, "Relink"))
    assert dialog.result() == QDialog.DialogCode.Accepted
    assert dialog.chosen == candidates[1]


def test_relink_browse_and_skip(qtbot, tmp_path, monkeypatch):
    other = tmp_path / "elsewhere" / "DJI_0042.MP4"
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *args: (str(other), ""))
    dialog = show(qtbot, RelinkDialog("DJI_0042.MP4", tmp_path, []))
    relink, skip = box_button(dialog, "Relink"), box_button(dialog, "Skip")
    assert not relink.isEnabled()
    child(dialog, QPushButton, "browse").menu().actions()[0].trigger()
    assert relink.isEnabled()
    click(qtbot, skip)
    assert dialog.chosen is None


def test_shortcuts_list_every_action_in_menu_order_then_the_mouse(qtbot):
    menus, actions = load_action_table()
    dialog = show(qtbot, ShortcutsDialog())
    table = child(dialog, QTableWidget, "shortcuts")
    assert table.rowCount() == len(actions) + len(MOUSE_GESTURES)
    rows = [[table.item(r, c).text() for c in range(3)] for r in range(table.rowCount())]
    in_order = sorted(actions, key=lambda a: menus.index(a.menu))
    assert [r[0] for r in rows[:len(actions)]] == [a.where for a in in_order]
    assert "Edit → Compute device" in [r[0] for r in rows]
    assert ["File", QKeySequence("Ctrl+S").toString(QKeySequence.SequenceFormat.NativeText),
            "Save project"] in rows
    assert rows[-1][0] == "Mouse" and rows[-1][1].endswith("click")
    assert table.editTriggers() == QTableWidget.EditTrigger.NoEditTriggers


def test_animal_refuses_an_empty_or_duplicate_id(qtbot):
    dialog = show(qtbot, AnimalDialog("", "", other_ids=["dolphin 1", "calf"]))
    id_edit, error = child(dialog, QLineEdit, "animal_id"), child(dialog, QLabel, "error")
    assert not ok_button(dialog).isEnabled() and "needs an ID" in error.text()
    qtbot.keyClicks(id_edit, " Dolphin 1")
    assert not ok_button(dialog).isEnabled() and "already called" in error.text()
    assert error.isVisible()
    qtbot.keyClicks(id_edit, "b")
    qtbot.keyClicks(child(dialog, QPlainTextEdit, "notes"), "nicked dorsal fin")
    assert ok_button(dialog).isEnabled() and not error.isVisible()
    click(qtbot, ok_button(dialog))
    assert dialog.result() == QDialog.DialogCode.Accepted
    assert (dialog.animal_id, dialog.notes) == ("Dolphin 1b", "nicked dorsal fin")


def test_launch_height_is_asked_with_no_value_filled_in(qtbot):
    """OK stays off until a plausible height is typed; a decimal comma is read as a point."""
    dialog = show(qtbot, LaunchHeightDialog(["DJI_0041.MP4", "DJI_0042.MP4"]))
    edit, error = child(dialog, QLineEdit, "launch_height"), child(dialog, QLabel, "error")
    assert edit.text() == "" and not ok_button(dialog).isEnabled()
    assert "2 clips (DJI_0041.MP4, DJI_0042.MP4)" in " ".join(
        label.text() for label in dialog.findChildren(QLabel))
    qtbot.keyClicks(edit, "600")
    assert not ok_button(dialog).isEnabled() and "not a launch height of -10–500 m" in error.text()
    edit.clear()
    qtbot.keyClicks(edit, "1,5")
    assert ok_button(dialog).isEnabled()
    click(qtbot, ok_button(dialog))
    assert dialog.result() == QDialog.DialogCode.Accepted and dialog.launch_height_m == 1.5


def test_handle_style_values(qtbot, monkeypatch):
    monkeypatch.setattr(QColorDialog, "getColor", lambda *args: QColor("#123456"))
    dialog = show(qtbot, HandleStyleDialog(HandleStyle(size_px=20, opacity=0.5, shape="ring")))
    assert dialog.style.size_px == 20 and dialog.style.shape == "ring"
    click(qtbot, child(dialog, QPushButton, "colour_b"))
    type_into(qtbot, child(dialog, QAbstractSpinBox, "size_px"), "30")
    type_into(qtbot, child(dialog, QAbstractSpinBox, "opacity"), "75")
    shape = child(dialog, QComboBox, "shape")
    shape.setCurrentIndex(shape.findData("cross"))
    assert dialog.style == HandleStyle(size_px=30.0, side_b_colour="#123456", opacity=0.75,
                                       shape="cross")
    assert child(dialog, QPushButton, "colour_b").text() == "#123456"


def test_questions_save_path_adds_the_project_suffix_and_cancel_is_none(qtbot, monkeypatch,
                                                                        tmp_path):
    from dolphinfit.core.project.project_file import PROJECT_SUFFIX
    from dolphinfit.ui.dialogs.questions import Questions

    parent = QWidget()
    qtbot.addWidget(parent)
    answers = [str(tmp_path / "survey"), str(tmp_path / f"b{PROJECT_SUFFIX}"), ""]
    monkeypatch.setattr(QFileDialog, "getSaveFileName",
                        staticmethod(lambda *args: (answers.pop(0), "")))
    ask = Questions(parent)
    assert ask.save_path(None) == tmp_path / f"survey{PROJECT_SUFFIX}"
    assert ask.save_path(tmp_path / f"a{PROJECT_SUFFIX}") == tmp_path / f"b{PROJECT_SUFFIX}"
    assert ask.save_path(None) is None


def test_questions_mesh_export_asks_the_format_then_the_folder(qtbot, monkeypatch, tmp_path):
    from dolphinfit.ui.dialogs.questions import Questions

    parent = QWidget()
    qtbot.addWidget(parent)
    formats, folders = [(".obj", True), (".ply", False), (".stl", True)], [str(tmp_path), ""]
    monkeypatch.setattr(QInputDialog, "getItem", staticmethod(lambda *a: formats.pop(0)))
    monkeypatch.setattr(QFileDialog, "getExistingDirectory",
                        staticmethod(lambda *a: folders.pop(0)))
    ask = Questions(parent)
    assert ask.mesh_export(tmp_path) == (tmp_path, ".obj")
    assert ask.mesh_export(tmp_path) is None     # format cancelled: no folder asked
    assert ask.mesh_export(tmp_path) is None     # folder cancelled
    assert not formats and not folders


def test_help_manual_opens_the_built_manual_or_says_how_to_build_it(qtbot, tmp_path,
                                                                     monkeypatch):
    """Built: the browser gets the local index page. Not built: a warning naming the missing
    page and `make docs`, and nothing opened."""
    from PySide6.QtWidgets import QWidget

    from dolphinfit.ui.dialogs import questions

    opened, told = [], []
    monkeypatch.setattr(questions.QDesktopServices, "openUrl", lambda url: opened.append(url))
    parent = QWidget()
    qtbot.addWidget(parent)
    ask = questions.Questions(parent)
    ask.warn = lambda title, text: told.append(text)
    index = tmp_path / "site" / "index.html"
    monkeypatch.setattr(questions, "MANUAL_INDEX", index)
    ask.show_manual()
    assert opened == [] and "make docs" in told[0] and str(index) in told[0]
    index.parent.mkdir()
    index.write_text("<html></html>")
    ask.show_manual()
    assert [url.toLocalFile() for url in opened] == [str(index)]


def test_the_about_box_gives_the_version_licence_and_citation():
    from dolphinfit.ui.dialogs.questions import ABOUT, version

    text = ABOUT.format(version=version())
    assert version() != "unknown" and f"dolphinfit {version()}" in text
    assert "MIT licence" in text and "arXiv:2504.15782" in text
