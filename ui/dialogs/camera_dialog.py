"""The clip's camera and video mode: a named preset, or focal length, sensor width (or pixel
size: sensor width = pixel size × image width) and image size typed by hand, with the focal
length in pixels and the GSD they give; for the clips selected with it, and, where ticked,
every clip of the clip's video size. A clip without a camera (a still whose EXIF names none)
shows "unknown" until one is chosen or typed; OK waits for it."""

import math
from dataclasses import dataclass, replace

from PySide6.QtCore import QSignalBlocker, Qt
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDialog, QDialogButtonBox,
                               QDoubleSpinBox, QFormLayout, QHBoxLayout, QInputDialog, QLabel,
                               QMessageBox, QPushButton, QSpinBox, QVBoxLayout, QWidget)

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
PIXEL_SIZE_MAX_UM = 100.0  # core.limits.PIXEL_DIMENSION_MM
IMAGE_SIZE_RANGE_PX = (16, 100_000)
MM_DECIMALS = 4
UM_DECIMALS = 4  # 3.9167 µm: a pixel size typed as the maker or MorphoMetriX gives it
UM_PER_MM = 1000.0
UNKNOWN = 0.0  # a lens field not known yet, shown as "unknown"
COMBO_MIN_CHARS = 48  # long preset descriptions are elided, not widening the dialog
EDITED_SOURCE = "entered in the camera dialog"


def _lens_spin(name: str, maximum: float, unit: str = "mm",
               decimals: int = MM_DECIMALS) -> QDoubleSpinBox:
    """A lens field from UNKNOWN (shown as "unknown": no camera yet) to ``maximum``."""
    spin = QDoubleSpinBox(objectName=name, suffix=f" {unit}", decimals=decimals)
    spin.setRange(UNKNOWN, maximum)
    spin.setSpecialValueText("unknown")
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
    """Choose a clip's camera: ``camera`` (None: unknown) and ``preset_name`` (None once a
    value is edited, or for a photo's own camera).

    ``width_px``, ``height_px``: the clip's image size, checked against the camera's;
    ``num_clips``: how many clips are selected with it (all take the camera);
    ``for_clips``: False where the camera is for something else than clips (a calibration's
    shots), which hides "Use for every clip of this video size".
    """

    def __init__(self, current: CameraPreset | None, preset_name: str | None, width_px: int,
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
        if current is not None and preset_name is not None and preset_name not in self._presets:
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
        self._spins = (_lens_spin("focal_mm", FOCAL_RANGE_MM[1]),
                       _lens_spin("sensor_width_mm", SENSOR_WIDTH_RANGE_MM[1]),
                       _px_spin("image_width_px"), _px_spin("image_height_px"))
        self._pixel = _lens_spin("pixel_size_um", PIXEL_SIZE_MAX_UM, "µm", UM_DECIMALS)
        self._pixel.valueChanged.connect(self._on_pixel_edited)
        form = QFormLayout()
        form.addRow("Preset:", self._combo)
        for label, spin in zip(("Focal length (real, not 35 mm-equivalent):",
                                "Sensor width read in this video mode:", "Image width:",
                                "Image height:"), self._spins):
            form.addRow(label, spin)
            spin.valueChanged.connect(self._on_edited)
        form.insertRow(3, "or pixel size (sensor width ÷ image width):", self._pixel)
        self._derived = QLabel(objectName="derived", wordWrap=True)
        self._warning = MessageLabel(objectName="mismatch")
        self._use_clip_size = QPushButton(
            f"Use the clip's size ({self._clip_size[0]}×{self._clip_size[1]} px)",
            objectName="use_clip_size")
        self._use_clip_size.clicked.connect(self._on_use_clip_size)
        self._every_of_size = QCheckBox(
            f"Use for every clip of this video size ({self._clip_size[0]}×"
            f"{self._clip_size[1]} px)", objectName="every_clip_of_size")
        self._save = QPushButton("Save as my preset…", objectName="save_preset")
        self._save.clicked.connect(self._save_as_preset)
        buttons = ok_cancel_buttons(self)
        self._ok = buttons.button(QDialogButtonBox.StandardButton.Ok)
        layout = QVBoxLayout(self)
        layout.addLayout(form)
        for widget in (self._derived, self._warning, self._use_clip_size, self._every_of_size,
                       self._status):
            layout.addWidget(widget)
        row = QHBoxLayout()
        row.addWidget(self._save)
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
        """Put the camera's values in the fields (no edit) and update the readouts; an
        unknown camera's lens fields show "unknown" at the clip's size."""
        camera = self._camera
        values = ((UNKNOWN, UNKNOWN, *self._clip_size) if camera is None else
                  (camera.focal_mm, camera.sensor_width_mm, camera.image_width_px,
                   camera.image_height_px))
        for spin, value in zip(self._spins, values):
            with QSignalBlocker(spin):
                spin.setValue(value)
        self._show_pixel_size()
        self._update_readouts()

    def _show_pixel_size(self) -> None:
        """The pixel size the sensor width and image width give (no edit)."""
        _, sensor, width, _ = self._spins
        with QSignalBlocker(self._pixel):
            self._pixel.setValue(sensor.value() / width.value() * UM_PER_MM)

    def _update_readouts(self) -> None:
        self._ok.setEnabled(self._camera is not None)
        self._save.setEnabled(self._camera is not None)
        if self._camera is None:
            self._derived.setText("Camera unknown: choose a preset, or enter the focal length "
                                  "and the pixel size or the sensor width")
            self._warning.show_message("", "warning")
            self._use_clip_size.setVisible(False)
            return
        intrinsics = self._camera.intrinsics()
        gsd_cm = intrinsics.gsd_m_per_px(GSD_ALTITUDE_M) * CM_PER_M
        origin = f"{self._camera.description}\n" if self._preset_name is None else ""
        approximate = ("\nApproximate: these values are not verified for this video mode."
                       if self._camera.approximate else "")
        self._derived.setText(
            f"{origin}Focal length {intrinsics.focal_px:.1f} px · GSD {gsd_cm:.2f} cm/px at "
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
        self._show_pixel_size()
        self._take_fields()

    def _on_pixel_edited(self, pixel_um: float) -> None:
        """A pixel size typed: the sensor width it gives at the image width (they are tied)."""
        _, sensor, width, _ = self._spins
        with QSignalBlocker(sensor):
            sensor.setValue(pixel_um / UM_PER_MM * width.value())
        self._take_fields()

    def _take_fields(self) -> None:
        """The camera of the fields' values (typed: not approximate); None while the focal
        length or the sensor width is unknown or below its range."""
        focal_mm, sensor_mm, width_px, height_px = (spin.value() for spin in self._spins)
        is_known = focal_mm >= FOCAL_RANGE_MM[0] and sensor_mm >= SENSOR_WIDTH_RANGE_MM[0]
        self._camera = entered_camera(
            self._camera, self._preset_name is not None, focal_mm, sensor_mm, width_px,
            height_px, source=EDITED_SOURCE) if is_known else None
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
    def camera(self) -> CameraPreset | None:
        """The chosen camera: a preset, or the values typed (named "edited"); None while
        unknown (OK is disabled then)."""
        return self._camera

    @property
    def preset_name(self) -> str | None:
        """The preset the camera is, None once its values were edited."""
        return self._preset_name

    @property
    def answer(self) -> CameraAnswer:
        """The camera, its preset and whether every clip of this video size takes it."""
        return CameraAnswer(self._camera, self._preset_name, self._every_of_size.isChecked())
