"""The clip's camera and video mode: a named preset, or focal length, sensor width and image
size typed by hand, with the focal length in pixels and the GSD they give; for the clips
selected with it, and, where ticked, every clip of the clip's video size."""

import math
from dataclasses import dataclass, replace

from PySide6.QtCore import QSignalBlocker, Qt
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDialog, QDoubleSpinBox, QFormLayout,
                               QHBoxLayout, QInputDialog, QLabel, QMessageBox, QPushButton,
                               QSpinBox, QVBoxLayout, QWidget)

from dolphinfit.core.camera_presets import (CameraPreset, load_presets, preset_resolution_mismatch,
                                 save_user_preset)
from dolphinfit.core.errors import InputError
from dolphinfit.core.project.clip_cameras import entered_camera
from dolphinfit.ui.dialogs.dialog_buttons import ok_cancel_buttons
from dolphinfit.ui.dialogs.message_label import MessageLabel

GSD_ALTITUDE_M = 20.0  # the altitude of the GSD readout (DESIGN.md §3's example)
CM_PER_M = 100.0
FOCAL_RANGE_MM = (0.5, 2000.0)
SENSOR_WIDTH_RANGE_MM = (0.5, 100.0)
IMAGE_SIZE_RANGE_PX = (16, 100_000)
MM_DECIMALS = 4
COMBO_MIN_CHARS = 48  # long preset descriptions are elided, not widening the dialog
EDITED_SOURCE = "entered in the camera dialog"


def _mm_spin(name: str, value_range: tuple[float, float]) -> QDoubleSpinBox:
    spin = QDoubleSpinBox(objectName=name, suffix=" mm", decimals=MM_DECIMALS)
    spin.setRange(*value_range)
    return spin


def _px_spin(name: str) -> QSpinBox:
    spin = QSpinBox(objectName=name, suffix=" px")
    spin.setRange(*IMAGE_SIZE_RANGE_PX)
    return spin


@dataclass(frozen=True)
class CameraAnswer:
    """The camera chosen, its preset (None: values edited) and whether every clip of the
    clip's video size takes it too."""

    camera: CameraPreset
    preset_name: str | None
    is_for_every_clip_of_size: bool = False


class CameraDialog(QDialog):
    """Choose a clip's camera: ``camera`` and ``preset_name`` (None once a value is edited).

    ``width_px``, ``height_px``: the clip's image size, checked against the camera's;
    ``num_clips``: how many clips are selected with it (all take the camera);
    ``for_clips``: False where the camera is for something else than clips (a calibration's
    shots), which hides "Use for every clip of this video size".
    """

    def __init__(self, current: CameraPreset, preset_name: str | None, width_px: int,
                 height_px: int, parent: QWidget | None = None, num_clips: int = 1,
                 for_clips: bool = True) -> None:
        super().__init__(parent)
        self.setWindowTitle("Camera and video mode" if num_clips == 1 else
                            f"Camera and video mode of {num_clips} clips")
        self._camera = current
        self._preset_name = preset_name
        self._clip_size = (width_px, height_px)
        self._status = MessageLabel(objectName="status")
        try:
            self._presets = load_presets()
        except InputError as exc:
            self._presets = {}
            self._status.show_message(f"Camera presets not loaded: {exc}", "error")
        if preset_name is not None and preset_name not in self._presets:
            self._presets[preset_name] = current  # a preset of the machine the project came from
        self._build()
        self._every_of_size.setVisible(for_clips)
        self._fill_combo()
        self._show_camera()

    def _build(self) -> None:
        self._combo = QComboBox(objectName="preset", placeholderText="edited: own values")
        self._combo.setSizeAdjustPolicy(
            QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self._combo.setMinimumContentsLength(COMBO_MIN_CHARS)
        self._combo.currentIndexChanged.connect(self._on_preset_chosen)
        self._spins = (_mm_spin("focal_mm", FOCAL_RANGE_MM),
                       _mm_spin("sensor_width_mm", SENSOR_WIDTH_RANGE_MM),
                       _px_spin("image_width_px"), _px_spin("image_height_px"))
        form = QFormLayout()
        form.addRow("Preset:", self._combo)
        for label, spin in zip(("Focal length (real, not 35 mm-equivalent):",
                                "Sensor width read in this video mode:", "Image width:",
                                "Image height:"), self._spins):
            form.addRow(label, spin)
            spin.valueChanged.connect(self._on_edited)
        self._derived = QLabel(objectName="derived", wordWrap=True)
        self._warning = MessageLabel(objectName="mismatch")
        self._use_clip_size = QPushButton(
            f"Use the clip's size ({self._clip_size[0]}×{self._clip_size[1]} px)",
            objectName="use_clip_size")
        self._use_clip_size.clicked.connect(self._on_use_clip_size)
        self._every_of_size = QCheckBox(
            f"Use for every clip of this video size ({self._clip_size[0]}×"
            f"{self._clip_size[1]} px)", objectName="every_clip_of_size")
        save = QPushButton("Save as my preset…", objectName="save_preset")
        save.clicked.connect(self._save_as_preset)
        buttons = ok_cancel_buttons(self)
        layout = QVBoxLayout(self)
        layout.addLayout(form)
        for widget in (self._derived, self._warning, self._use_clip_size, self._every_of_size,
                       self._status):
            layout.addWidget(widget)
        row = QHBoxLayout()
        row.addWidget(save)
        row.addStretch()
        row.addWidget(buttons)
        layout.addLayout(row)
        layout.setAlignment(self._use_clip_size, Qt.AlignmentFlag.AlignLeft)

    def _fill_combo(self) -> None:
        """List the presets ("name — description"), the current one selected."""
        with QSignalBlocker(self._combo):
            self._combo.clear()
            for name, preset in sorted(self._presets.items()):
                mark = " (approximate)" if preset.approximate else ""
                self._combo.addItem(f"{name} — {preset.description}{mark}", name)
            self._combo.setCurrentIndex(self._combo.findData(self._preset_name)
                                        if self._preset_name is not None else -1)

    def _show_camera(self) -> None:
        """Put the camera's values in the fields (no edit) and update the readouts."""
        camera = self._camera
        for spin, value in zip(self._spins, (camera.focal_mm, camera.sensor_width_mm,
                                             camera.image_width_px, camera.image_height_px)):
            with QSignalBlocker(spin):
                spin.setValue(value)
        self._update_readouts()

    def _update_readouts(self) -> None:
        intrinsics = self._camera.intrinsics()
        gsd_cm = intrinsics.gsd_m_per_px(GSD_ALTITUDE_M) * CM_PER_M
        approximate = ("\nApproximate: these values are not verified for this video mode."
                       if self._camera.approximate else "")
        self._derived.setText(
            f"Focal length {intrinsics.focal_px:.1f} px · GSD {gsd_cm:.2f} cm/px at "
            f"{GSD_ALTITUDE_M:g} m · horizontal field of view "
            f"{math.degrees(intrinsics.fov_x_rad):.1f}°{approximate}")
        mismatch = preset_resolution_mismatch(self._camera, *self._clip_size)
        self._warning.show_message(mismatch or "", "warning")
        self._use_clip_size.setVisible(mismatch is not None)

    def _on_preset_chosen(self, index: int) -> None:
        if index < 0:
            return
        self._preset_name = self._combo.itemData(index)
        self._camera = self._presets[self._preset_name]
        self._show_camera()

    def _on_edited(self) -> None:
        self._camera = entered_camera(self._camera, self._preset_name is not None,
                                      *(spin.value() for spin in self._spins),
                                      source=EDITED_SOURCE)
        self._preset_name = None
        with QSignalBlocker(self._combo):
            self._combo.setCurrentIndex(-1)
        self._update_readouts()

    def _on_use_clip_size(self) -> None:
        for spin, value in zip(self._spins[2:], self._clip_size):
            spin.setValue(value)

    def _save_as_preset(self) -> None:
        """Ask a name and save the fields as a user preset (replacing one of that name)."""
        name, ok = QInputDialog.getText(self, "Save as my preset", "Name of the preset:")
        name = name.strip()
        if not ok or not name:
            return
        if name in self._presets and QMessageBox.question(
                self, "Save as my preset", f"Replace the preset {name!r}?"
        ) != QMessageBox.StandardButton.Yes:
            return
        width, height = self._camera.image_width_px, self._camera.image_height_px
        preset = replace(self._camera, name=name, description=f"my preset, {width}×{height} px",
                         source=EDITED_SOURCE)
        try:
            path = save_user_preset(preset)
            self._presets = load_presets()
        except (InputError, OSError) as exc:
            QMessageBox.warning(self, "Preset not saved", str(exc))
            return
        self._camera, self._preset_name = preset, name
        self._fill_combo()
        self._update_readouts()
        self._status.show_message(f"Saved the preset {name!r} to {path}")

    @property
    def camera(self) -> CameraPreset:
        """The chosen camera: a preset, or the values typed (named "edited")."""
        return self._camera

    @property
    def preset_name(self) -> str | None:
        """The preset the camera is, None once its values were edited."""
        return self._preset_name

    @property
    def answer(self) -> CameraAnswer:
        """The camera, its preset and whether every clip of this video size takes it."""
        return CameraAnswer(self._camera, self._preset_name, self._every_of_size.isChecked())
