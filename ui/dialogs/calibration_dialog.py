"""Calibrate a drone's altimeter in the app: images of an object of known length, its two ends
clicked on each, the altitude recorded with each, and the fitted line drawn as the shots come
in (or a table of pixel lengths imported instead). The calibration holds for the camera the
shots were taken with: chosen in the dialog (the open clip's is offered first, never assumed),
or an imported table's own (its focal length, sensor width and image width columns, or the one
camera preset of its drone and video mode). No line is fitted until there is one. The clips it
corrects are ticked by the user; only clips of that camera can be.

Images are read and the line fitted in the background; the dialog only draws."""

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg
from matplotlib.figure import Figure
from PySide6.QtCore import QLineF, Qt
from PySide6.QtWidgets import (QAbstractItemView, QCheckBox, QComboBox, QDialog, QDoubleSpinBox,
                               QFormLayout, QGraphicsLineItem, QGridLayout, QHeaderView, QLabel,
                               QLineEdit, QPushButton, QSplitter, QTableWidget,
                               QTableWidgetItem, QVBoxLayout, QWidget)

from dolphinfit.core.camera_presets import CameraPreset, load_presets, table_camera
from dolphinfit.core.io.calibration_table import read_calibration_table
from dolphinfit.core.io.image_file import read_image
from dolphinfit.core.limits import BODY_LENGTH_M, LAUNCH_HEIGHT_M, in_range
from dolphinfit.core.measure.altitude_calibration import AltitudeCalibration, same_focal_px
from dolphinfit.core.measure.annotation import ALTITUDE_SOURCES
from dolphinfit.core.measure.calibration_plot import draw_altitude_calibration
from dolphinfit.core.project.calibrations import (
    UNKNOWN_ALTITUDE_M,
    FRAME_MARK,
    clip_shots,
    fitted_calibration,
    read_shot_image,
    shots_from_table,
    srt_is_relative,
)
from dolphinfit.core.project.model import AltitudeCalibrationSet, ObjectShot
from dolphinfit.ui.dialogs.camera_dialog import CameraDialog
from dolphinfit.ui.dialogs.dialog_buttons import ok_cancel_buttons
from dolphinfit.ui.dialogs.message_label import MessageLabel
from dolphinfit.ui.widgets.canvas import FrameCanvas
from dolphinfit.ui.widgets.overlay_items import cosmetic_pen
from dolphinfit.ui.workers.background import BackgroundJobs

ALTIMETERS = tuple(source for source in ALTITUDE_SOURCES if source != "manual")
COLUMNS = ("image", "recorded altitude (m)", "length (px)")
DEFAULT_OBJECT_LENGTH_M = 2.0
FRAME_STEP = 30          # of a video, one frame a second at 30 frames/s
KEPT_IMAGES = 4
DEFAULT_ALTIMETER = "barometer"   # what most drones carry
LINE_COLOUR = Qt.GlobalColor.yellow
NO_CAMERA = "choose the camera the shots were taken with (Camera…)"


@dataclass(frozen=True)
class CalibrationChoice:
    """The dialog's answer: the calibration set and the clips (indices) it corrects."""

    calibration: AltitudeCalibrationSet
    clip_indices: tuple[int, ...]


@dataclass(frozen=True)
class ImportedTable:
    """A calibration table read for the dialog: its shots, the object's length and the camera
    (with where it was found) where the table states them."""

    name: str
    shots: tuple[ObjectShot, ...]
    object_length_m: float | None
    camera: tuple[CameraPreset, str] | None


def read_table(path: Path, altimeter: str | None) -> ImportedTable:
    """``path``'s shots, object length and camera, as `dolphinfit calibrate altitude` reads
    them; InputError naming the file when it cannot be used."""
    table = read_calibration_table(path, altimeter)
    length_m = table.common_value("object_length_m")
    if length_m is not None:
        in_range(length_m, BODY_LENGTH_M, f"{path}: object length")
    return ImportedTable(path.name, shots_from_table(table), length_m,
                         table_camera(table, load_presets()))


class CalibrationDialog(QDialog):
    """Build or edit an altitude calibration (module doc).

    ``current``: the set to edit (its camera kept), or None for a new one (no camera yet);
    ``clip_camera``, ``clip_preset``: the open clip's camera and preset name, offered first
    when the camera is chosen; ``clips``: (index, name, focal length px) of the project's
    clips, ``ticked`` those it corrects now."""

    def __init__(self, current: AltitudeCalibrationSet | None, clip_camera: CameraPreset,
                 clip_preset: str | None, clips: list[tuple[int, str, float]],
                 ticked: set[int], parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Altitude calibration")
        self.resize(1100, 720)
        self.jobs = BackgroundJobs(self)
        self._camera = current.camera if current else None
        self._camera_origin = "the calibration's"   # where self._camera came from
        self._clip_camera = (clip_camera, clip_preset)
        self._shots_size_px: tuple[int, int] | None = None   # (W, H) of the images read
        self._why_no_line = "the line is being fitted"
        self._shots: list[ObjectShot] = list(current.shots) if current else []
        self._images: dict[str, np.ndarray] = {}   # the last few shots' images, for clicking
        self._pending: set[str] = set()   # shots added here whose ends are not clicked yet
        self._clicks: list[tuple[float, float]] = []
        self._generation = 0   # of the fit asked for last
        self.calibration: AltitudeCalibration | None = None

        self.name = QLineEdit(current.name if current else "", objectName="name")
        self.name.setPlaceholderText("e.g. Mavic 3 barometer")
        self.object_length = QDoubleSpinBox(objectName="object_length", suffix=" m",
                                            decimals=3, minimum=0.05, maximum=50.0)
        self.object_length.setValue(current.object_length_m if current
                                    else DEFAULT_OBJECT_LENGTH_M)
        self.altimeter = QComboBox(objectName="altimeter")
        self.altimeter.addItems(ALTIMETERS)
        self.altimeter.setCurrentText(current.altimeter if current else DEFAULT_ALTIMETER)
        self.table = QTableWidget(0, len(COLUMNS), objectName="shots")
        self.table.setHorizontalHeaderLabels(COLUMNS)
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        header = self.table.horizontalHeader()   # the numbers whole, the names give way
        header.setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(0, QHeaderView.ResizeMode.Stretch)
        self.canvas = FrameCanvas()
        self.line = QGraphicsLineItem()
        self.line.setPen(cosmetic_pen(LINE_COLOUR))
        self.canvas.scene().addItem(self.line)
        self.figure = Figure(figsize=(5, 3.6), layout="tight")
        self.plot = FigureCanvasQTAgg(self.figure)
        self.summary = QLabel(objectName="summary", wordWrap=True)
        self.status = MessageLabel(objectName="status")
        self.camera = QLabel(objectName="camera", wordWrap=True)
        self.clip_boxes = {index: QCheckBox(name) for index, name, _ in clips}
        self._clip_focal_px = {index: focal_px for index, _, focal_px in clips}
        for index, box in self.clip_boxes.items():
            box.setChecked(index in ticked)
        self._layout()
        self._show_camera()
        self.object_length.valueChanged.connect(self._refit)
        self.name.textChanged.connect(self._refit)
        self.table.itemSelectionChanged.connect(self._show_selected)
        self.table.itemChanged.connect(self._on_item_changed)
        self.canvas.image_clicked.connect(self._on_clicked)
        self._fill_table()
        self._refit()

    def _layout(self) -> None:
        form = QFormLayout()
        form.addRow("Name", self.name)
        form.addRow("Object length", self.object_length)
        form.addRow("Altimeter", self.altimeter)
        choose = QPushButton("Camera…", objectName="choose_camera")
        choose.setToolTip("the camera and video mode the shots were taken with")
        choose.clicked.connect(self._choose_camera)
        camera = QVBoxLayout()
        camera.addWidget(self.camera)
        camera.addWidget(choose, alignment=Qt.AlignmentFlag.AlignLeft)
        form.addRow("Camera", camera)
        add = QPushButton("Add images…", objectName="add_images")
        add.clicked.connect(self._ask_images)
        frames = QPushButton("Add clip frames…", objectName="add_clip_frames")
        frames.setToolTip(f"every {FRAME_STEP}th frame of a video, at the altitudes of its SRT")
        frames.clicked.connect(self._ask_clip)
        imported = QPushButton("Import table…", objectName="import_table")
        imported.setToolTip("pixel lengths and altitudes: our CSV, MedidoR's calib.xlsx or "
                            "Xcertainty's tables")
        imported.clicked.connect(self._ask_table)
        remove = QPushButton("Remove shot", objectName="remove_shot")
        remove.clicked.connect(self.remove_selected)
        buttons = QGridLayout()   # two rows, so that the image keeps the room
        for index, button in enumerate((add, frames, imported, remove)):
            buttons.addWidget(button, index // 2, index % 2)
        left = QVBoxLayout()
        left.addLayout(form)
        left.addWidget(self.table)
        left.addLayout(buttons)
        left.addWidget(QLabel("Click the object's two ends on the selected shot's image (the "
                              "wheel zooms); type the altitude recorded with it.",
                              wordWrap=True))
        right = QVBoxLayout()
        right.addWidget(self.plot)
        right.addWidget(self.summary)
        right.addWidget(QLabel("Correct the altitudes of these clips (only those of the "
                               "calibration's camera can be):", wordWrap=True))
        for box in self.clip_boxes.values():
            right.addWidget(box)
        right.addStretch()
        split = QSplitter()
        for layout in (left, right):
            holder = QWidget()
            holder.setLayout(layout)
            split.addWidget(holder)
        split.insertWidget(1, self.canvas)
        split.setSizes([330, 450, 320])
        outer = QVBoxLayout(self)
        outer.addWidget(split)
        outer.addWidget(self.status)
        outer.addWidget(ok_cancel_buttons(self))

    # ------------------------------------------------------------------ camera
    def _choose_camera(self) -> None:
        camera = self.ask_camera()
        if camera is not None:
            self.set_camera(camera, "chosen with Camera…")

    def ask_camera(self) -> CameraPreset | None:
        """The shots' camera, chosen in the camera dialog (the calibration's, else the open
        clip's, offered first; checked against the shots' image size); None when cancelled."""
        start, preset = ((self._camera, None) if self._camera is not None
                         else self._clip_camera)
        width, height = self._shots_size_px or (start.image_width_px, start.image_height_px)
        dialog = CameraDialog(start, preset, width, height, self, for_clips=False)
        chosen = dialog.camera if dialog.exec() else None
        dialog.deleteLater()
        return chosen

    def set_camera(self, camera: CameraPreset, origin: str) -> None:
        """Fit with ``camera`` (``origin``: where it came from, shown beside it)."""
        self._camera, self._camera_origin = camera, origin
        if NO_CAMERA in self.status.text():   # asked for, now given
            self.status.clear_message()
        self._show_camera()
        self._refit()

    def _show_camera(self) -> None:
        """Say which camera the line is for; only clips of that camera can be ticked."""
        camera = self._camera
        if camera is None:
            self.camera.setText(f"none: {NO_CAMERA}")
        else:
            self.camera.setText(
                f"{camera.name}: focal {camera.focal_mm:g} mm, sensor "
                f"{camera.sensor_width_mm:g} mm, {camera.image_width_px} px wide "
                f"({self._camera_origin})")
        for index, box in self.clip_boxes.items():
            same = camera is not None and same_focal_px(self._clip_focal_px[index],
                                                        camera.intrinsics().focal_px)
            box.setEnabled(same)
            box.setToolTip("" if same else "a clip of another camera (or none chosen)")
            if not same:
                box.setChecked(False)

    # ------------------------------------------------------------------ shots
    def _ask_images(self) -> None:
        from PySide6.QtWidgets import QFileDialog

        names, _ = QFileDialog.getOpenFileNames(
            self, "Images of the calibration object", "",
            "Images (*.jpg *.jpeg *.png *.tif *.tiff *.dng);;All files (*)")
        self.add_images([Path(name) for name in names])

    def _ask_table(self) -> None:
        from PySide6.QtWidgets import QFileDialog

        name, _ = QFileDialog.getOpenFileName(
            self, "Table of the object's pixel lengths", "",
            "Tables (*.csv *.xlsx *.rda *.RData);;All files (*)")
        if name:
            self.import_table(Path(name), self.altimeter.currentText())

    def _ask_clip(self) -> None:
        from PySide6.QtWidgets import QFileDialog

        name, _ = QFileDialog.getOpenFileName(self, "A video of the calibration object", "",
                                              "Videos (*.mp4 *.mov *.MP4 *.MOV);;All files (*)")
        if name:
            self.add_clip_frames(Path(name))

    def add_clip_frames(self, video: Path, every: int | None = None) -> None:
        """Every ``every``-th frame of ``video`` as a shot to measure, its altitude from the
        video's SRT (shots where the object is not seen are removed by the user); an SRT of
        heights above the take-off point asks for that point's height above the water
        first."""
        step = FRAME_STEP if every is None else every

        def add(relative: bool) -> None:
            launch_m = self.ask_launch_height(video) if relative else 0.0
            if launch_m is not None:
                self.jobs.run(lambda: clip_shots(video, step, launch_m), self._on_clip_shots,
                              lambda why: self.status.show_message(why, "error"))

        self.jobs.run(lambda: srt_is_relative(video), add,
                      lambda why: self.status.show_message(why, "error"))

    def ask_launch_height(self, video: Path) -> float | None:
        """The take-off point's height above the water (m) for a video whose SRT records
        height above it; None when the user cancels."""
        from PySide6.QtWidgets import QInputDialog

        value, ok = QInputDialog.getDouble(
            self, "Launch height", f"{video.name} records the height above the take-off "
            "point.\nHow high was the take-off point above the water (m)?", 0.0,
            LAUNCH_HEIGHT_M.low, LAUNCH_HEIGHT_M.high, 2)
        return value if ok else None

    def _on_clip_shots(self, found: tuple[tuple[ObjectShot, ...], str]) -> None:
        shots, note = found
        if note:
            self.status.show_message(note, "warning")
        self._pending.update(shot.image for shot in shots)
        self._shots += shots
        self._fill_table()
        self.table.selectRow(len(self._shots) - len(shots))

    def add_images(self, paths: list[Path]) -> None:
        """Read ``paths`` in the background and add a shot for each (its length once its two
        ends are clicked; its altitude as recorded, to be typed)."""
        for path in paths:
            self.jobs.run(lambda p=path: (p, read_image(p)), self._on_image_read,
                          lambda why: self.status.show_message(why, "error"))

    def import_table(self, path: Path, altimeter: str | None = None) -> None:
        """Add a table's rows (our CSV, MedidoR's or Xcertainty's) as shots, with its object
        length and camera where it states them."""
        self.jobs.run(lambda: read_table(path, altimeter), self._on_table_read,
                      lambda why: self.status.show_message(why, "error"))

    def _on_table_read(self, table: ImportedTable) -> None:
        """The table's shots added, unless it states a camera other than the calibration's."""
        camera, origin = table.camera or (None, "")
        if camera is not None and self._camera is not None and not same_focal_px(
                camera.intrinsics().focal_px, self._camera.intrinsics().focal_px):
            self.status.show_message(
                f"{table.name}'s camera ({camera.name}, {origin}) is not the calibration's "
                f"({self._camera.name}): one calibration holds for one camera", "error")
            return
        self._shots += table.shots
        self._fill_table()
        notes = [f"{len(table.shots)} shots from {table.name}"]
        if table.object_length_m is not None:
            notes.append(f"the object {table.object_length_m:g} m long (the table's)")
            self.object_length.setValue(table.object_length_m)
        if camera is not None and self._camera is None:
            notes.append(f"camera {camera.name} ({origin})")
            self.set_camera(camera, origin)
        elif self._camera is None:
            notes.append(f"the table does not say its camera: {NO_CAMERA}")
        self.status.show_message("; ".join(notes), "info" if self._camera else "warning")
        self._refit()

    def _on_image_read(self, read: tuple[Path, np.ndarray]) -> None:
        path, rgb = read
        if not self._of_this_camera(str(path), rgb):
            return
        self._remember(str(path), rgb)
        self._pending.add(str(path))
        self._shots.append(ObjectShot(str(path), UNKNOWN_ALTITUDE_M, 1.0))
        self._fill_table()
        self.table.selectRow(len(self._shots) - 1)

    def _of_this_camera(self, image: str, rgb: np.ndarray) -> bool:
        """Whether ``image`` is as wide as the camera's images (while none is chosen, as the
        other shots'); an error shown when it is not."""
        height, width = rgb.shape[:2]
        if self._camera is not None:
            expected, whose = self._camera.image_width_px, "the camera's images are"
        elif self._shots_size_px is not None:
            expected, whose = self._shots_size_px[0], "the other shots are"
        else:
            expected, whose = width, ""
        if width != expected:
            self.status.show_message(f"{Path(image).name} is {width} px wide; {whose} "
                                     f"{expected} px: not a shot of this camera", "error")
            return False
        self._shots_size_px = (width, height)
        return True

    def remove_selected(self) -> None:
        row = self.table.currentRow()
        if 0 <= row < len(self._shots):
            self._pending.discard(self._shots.pop(row).image)
            self._fill_table()
            self._refit()

    def _fill_table(self) -> None:
        self.table.blockSignals(True)
        self.table.setRowCount(len(self._shots))
        for row, shot in enumerate(self._shots):
            measured = shot.image not in self._pending
            cells = (Path(shot.image).name, f"{shot.recorded_altitude_m:g}",
                     f"{shot.pixel_length:.1f}" if measured else "click its ends")
            for column, text in enumerate(cells):
                item = QTableWidgetItem(text)
                if column != 1:
                    item.setFlags(item.flags() & ~Qt.ItemFlag.ItemIsEditable)
                self.table.setItem(row, column, item)
        self.table.blockSignals(False)

    def _on_item_changed(self, item: QTableWidgetItem) -> None:
        """A recorded altitude typed into the table."""
        row = item.row()
        try:
            altitude = float(item.text())
            self._shots[row] = replace(self._shots[row], recorded_altitude_m=altitude)
        except ValueError:
            self.status.show_message(f"row {row + 1}: the recorded altitude must be a positive "
                                     f"number of metres, not {item.text()!r}", "error")
            self._fill_table()
            return
        self._refit()

    def set_altitude(self, row: int, altitude_m: float) -> None:
        """Type ``altitude_m`` into the altitude cell of ``row`` (as a user does)."""
        self.table.item(row, 1).setText(f"{altitude_m:g}")

    def _show_selected(self) -> None:
        self._clicks = []
        row = self.table.currentRow()
        shot = self._shots[row] if 0 <= row < len(self._shots) else None
        if shot is not None and shot.image not in self._images and _readable(shot.image):
            self.jobs.run(lambda: read_shot_image(shot.image),   # a frame, or an earlier shot
                          lambda rgb: self._on_shot_image(shot.image, rgb),
                          lambda why: self.status.show_message(why, "error"))
        if shot is None or shot.image not in self._images:
            self.line.hide()
            return
        self.canvas.set_frame(self._images[shot.image])
        self.canvas.fit_to_window()
        self._draw_ends(shot.ends_px)

    def _remember(self, image: str, rgb: np.ndarray) -> None:
        """Keep ``image`` for clicking, and only the last few (a video's frames are large)."""
        self._images[image] = rgb
        while len(self._images) > KEPT_IMAGES:
            del self._images[next(iter(self._images))]

    def _on_shot_image(self, image: str, rgb: np.ndarray) -> None:
        """A shot's image read when it was selected, so that its ends can be clicked."""
        if not self._of_this_camera(image, rgb):
            return
        self._remember(image, rgb)
        row = self.table.currentRow()
        if 0 <= row < len(self._shots) and self._shots[row].image == image:
            self._show_selected()

    def _draw_ends(self, ends) -> None:
        if ends is None:
            self.line.hide()
            return
        (u0, v0), (u1, v1) = ends
        self.line.setLine(QLineF(u0, v0, u1, v1))
        self.line.show()

    def _on_clicked(self, u: float, v: float, _modifiers: Qt.KeyboardModifier) -> None:
        row = self.table.currentRow()
        if not (0 <= row < len(self._shots)) or self._shots[row].image not in self._images:
            return
        self._clicks = [*self._clicks[-1:], (u, v)] if len(self._clicks) < 2 else [(u, v)]
        if len(self._clicks) < 2:
            self.line.hide()
            return
        ends = (self._clicks[0], self._clicks[1])
        length = float(np.hypot(ends[1][0] - ends[0][0], ends[1][1] - ends[0][1]))
        if length < 1.0:
            return
        self._shots[row] = replace(self._shots[row], pixel_length=length, ends_px=ends)
        self._pending.discard(self._shots[row].image)
        self._draw_ends(ends)
        self._fill_table()
        self.table.selectRow(row)
        self._refit()

    # ------------------------------------------------------------------ the fit
    def _measured(self) -> tuple[ObjectShot, ...]:
        return tuple(shot for shot in self._shots if shot.image not in self._pending)

    def calibration_set(self) -> AltitudeCalibrationSet:
        """The set as entered (ValueError saying what is missing)."""
        if self._camera is None:
            raise ValueError(NO_CAMERA)
        if self._shots_size_px and self._shots_size_px[0] != self._camera.image_width_px:
            raise ValueError(f"the shots' images are {self._shots_size_px[0]} px wide, the "
                             f"camera's {self._camera.image_width_px} px: choose the camera "
                             f"the shots were taken with (Camera…)")
        return AltitudeCalibrationSet(self.name.text().strip() or "unnamed calibration",
                                      self.object_length.value(), self._camera,
                                      self.altimeter.currentText(), self._measured())

    def _refit(self) -> None:
        self._generation += 1
        try:
            calibration_set = self.calibration_set()
        except ValueError as exc:
            self._show_fit(None, str(exc))
            return
        self.jobs.run(lambda: fitted_calibration(calibration_set),
                      lambda fitted, g=self._generation: g == self._generation
                      and self._show_fit(fitted, ""),
                      lambda why, g=self._generation: g == self._generation
                      and self._show_fit(None, why))

    def _show_fit(self, calibration: AltitudeCalibration | None, why: str) -> None:
        self.calibration, self._why_no_line = calibration, why
        self.figure.clear()
        if calibration is None:
            self.summary.setText(f"No line yet: {why}")
        else:
            draw_altitude_calibration(self.figure.add_subplot(), self._measured(), calibration)
            low, high = calibration.slope_ci
            self.summary.setText(
                f"true altitude = {calibration.intercept_m:+.2f} m + {calibration.slope:.4f} × "
                f"recorded (scale {low:.4f}–{high:.4f}); spread "
                f"{100 * calibration.residual_sd_fraction:.2f} % of the altitude"
                + (f"; check {', '.join(Path(o).name for o in calibration.outliers)}"
                   if calibration.outliers else ""))
        self.plot.draw_idle()

    def choice(self) -> CalibrationChoice:
        """The answer once accepted."""
        return CalibrationChoice(self.calibration_set(),
                                 tuple(i for i, box in self.clip_boxes.items() if box.isChecked()))

    def accept(self) -> None:
        """Only a calibration that gives a line is accepted."""
        if self.calibration is None:
            self.status.show_message(f"No line yet: {self._why_no_line}", "error")
            return
        if not self.name.text().strip():
            self.status.show_message("Name the calibration (the drone and altimeter).",
                                     "error")
            return
        super().accept()


def _readable(image: str) -> bool:
    """Whether a shot's image (a file, or a video's frame) is there to be read again."""
    return Path(image.partition(FRAME_MARK)[0]).is_file()

