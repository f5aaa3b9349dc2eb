"""Where a clip's altitude comes from: its SRT sidecar, another file, or a constant.

The chosen file is read here (altitude files are small, a few MB at most) so the dialog knows
whether its altitude is relative to the take-off point, which then needs a launch height, and
can preview it. Each file is read once, without launch height or time offset; the previewed
range adds the launch height as typed.
"""

import math
from pathlib import Path

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtGui import QDoubleValidator, QGuiApplication
from PySide6.QtWidgets import (QButtonGroup, QComboBox, QDialog, QDialogButtonBox,
                               QDoubleSpinBox, QFileDialog, QFormLayout, QGridLayout, QLineEdit,
                               QPushButton, QRadioButton, QVBoxLayout, QWidget)

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_samples import AltitudeSamples
from dolphinfit.core.io.telemetry import (
    READER_KINDS, find_srt_sidecar, read_altitude, summarize_samples,
)
from dolphinfit.core.io.video import Clip
from dolphinfit.core.measure.annotation import ALTITUDE_SOURCE_OF_KIND, ALTITUDE_SOURCES
from dolphinfit.core.project.model import AltitudeSpec
from dolphinfit.core.project.project_file import relative_media_path
from dolphinfit.ui.dialogs.dialog_buttons import ok_cancel_buttons
from dolphinfit.ui.dialogs.message_label import MessageLabel

CONSTANT_RANGE_M = (1.0, 500.0)
DEFAULT_CONSTANT_M = 20.0  # a typical survey height over dolphins (DESIGN.md §3)
LAUNCH_HEIGHT_RANGE_M = (0.0, 500.0)
TIME_OFFSET_LIMIT_S = 86400.0  # a day either way
_PATTERNS = " ".join(f"*{s} *{s.upper()}" for s in READER_KINDS)
FILE_FILTER = f"Altitude files: DJI SRT, altitude CSV, laser log ({_PATTERNS});;All files (*)"


class AltitudeDialog(QDialog):
    """Choose a clip's altitude; ``spec`` is the result (paths relative to the project).

    OK stays disabled while the chosen file cannot be read, holds no altitude, or needs a
    launch height that is not given.
    """

    def __init__(self, media_path: Path, project_dir: Path, clip: Clip,
                 current: AltitudeSpec | None = None, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._media_path = Path(media_path)
        self._project_dir = Path(project_dir)
        self._clip = clip
        self._sidecar = find_srt_sidecar(self._media_path)
        self._file: Path | None = None
        self._reads: dict[Path, AltitudeSamples | str] = {}  # samples, or why not
        self._problem = ""
        self.setWindowTitle(f"Altitude of {self._media_path.name}")
        self._build()
        self._load(current)

    def _build(self) -> None:
        sidecar = self._sidecar.name if self._sidecar is not None else "none beside the clip"
        self._sidecar_radio = QRadioButton(f"The clip's SRT: {sidecar}", objectName="sidecar")
        self._sidecar_radio.setEnabled(self._sidecar is not None)
        self._file_radio = QRadioButton("Another file:", objectName="file")
        self._path_edit = QLineEdit(readOnly=True, placeholderText="SRT, altitude CSV or laser log")
        browse = QPushButton("Browse…", objectName="browse")
        browse.clicked.connect(self._browse)
        self._constant_radio = QRadioButton("Constant altitude:", objectName="constant")
        self._constant_spin = QDoubleSpinBox(objectName="constant_m", suffix=" m", decimals=2)
        self._constant_spin.setRange(*CONSTANT_RANGE_M)
        self._constant_spin.setValue(DEFAULT_CONSTANT_M)
        self._constant_spin.valueChanged.connect(self._refresh)

        self._choices = QButtonGroup(self)
        choices = QGridLayout()
        for row, (radio, *fields) in enumerate(((self._sidecar_radio,),
                                                (self._file_radio, self._path_edit, browse),
                                                (self._constant_radio, self._constant_spin))):
            self._choices.addButton(radio)
            for column, widget in enumerate((radio, *fields)):
                choices.addWidget(widget, row, column)
        self._choices.buttonToggled.connect(self._on_choice_toggled)
        self._choices.buttonClicked.connect(self._preset_source)

        self._launch_edit = QLineEdit(objectName="launch_height_m",
                                      placeholderText="take-off point above the water")
        self._launch_validator = QDoubleValidator(*LAUNCH_HEIGHT_RANGE_M, 3, self._launch_edit)
        self._launch_edit.setValidator(self._launch_validator)
        self._launch_edit.textChanged.connect(self._refresh)
        self._offset_spin = QDoubleSpinBox(objectName="time_offset_s", suffix=" s", decimals=3)
        self._offset_spin.setRange(-TIME_OFFSET_LIMIT_S, TIME_OFFSET_LIMIT_S)
        self._offset_spin.setToolTip("Log time (s after the log's first row) at the clip's "
                                     "first frame")
        self._source_combo = QComboBox(objectName="source")
        self._source_combo.addItems(ALTITUDE_SOURCES)
        self._source_combo.setToolTip("Sets the altitude error used by the uncertainty")
        form = QFormLayout()
        form.addRow("Launch height (m):", self._launch_edit)
        form.addRow("Time offset, laser logs (s):", self._offset_spin)
        form.addRow("Altitude source:", self._source_combo)

        self._preview = MessageLabel(objectName="preview")
        self._error = MessageLabel(objectName="error")
        buttons = ok_cancel_buttons(self)
        self._ok = buttons.button(QDialogButtonBox.StandardButton.Ok)
        layout = QVBoxLayout(self)
        for item in (choices, form):
            layout.addLayout(item)
        for widget in (self._preview, self._error, buttons):
            layout.addWidget(widget)

    def _load(self, current: AltitudeSpec | None) -> None:
        """Show ``current``, or pre-select the sidecar, else a constant (still) or a file."""
        if current is None:
            radio = (self._sidecar_radio if self._sidecar is not None
                     else self._constant_radio if self._clip.num_frames == 1
                     else self._file_radio)
        elif current.path is None:
            self._constant_spin.setValue(current.constant_m)
            radio = self._constant_radio
        else:
            path = (self._project_dir / current.path).resolve()
            if self._sidecar is not None and path == self._sidecar.resolve():
                radio = self._sidecar_radio
            else:
                self._set_file(path)
                radio = self._file_radio
            self._launch_edit.setText(self._launch_validator.locale().toString(
                current.launch_height_m, "g", 6))
            self._offset_spin.setValue(current.time_offset_s)
        radio.setChecked(True)
        self._refresh()
        if current is None:
            self._preset_source()
        else:
            self._source_combo.setCurrentText(current.source)

    def _on_choice_toggled(self, _button: QRadioButton, checked: bool) -> None:
        if checked:  # the button turned off toggles too
            self._refresh()

    def _set_file(self, path: Path) -> None:
        self._file = path
        self._reads.pop(path, None)  # read it afresh: it may have changed
        self._path_edit.setText(str(path))

    def _browse(self) -> None:
        start = self._file.parent if self._file is not None else self._media_path.parent
        name, _ = QFileDialog.getOpenFileName(self, "Altitude file", str(start), FILE_FILTER)
        if not name:
            return
        self._set_file(Path(name))
        self._file_radio.setChecked(True)
        self._refresh()
        self._preset_source()

    def _chosen_path(self) -> Path | None:
        """The file the choice names (None for a constant or no file yet)."""
        if self._sidecar_radio.isChecked():
            return self._sidecar
        return self._file if self._file_radio.isChecked() else None

    def _read(self, path: Path) -> AltitudeSamples | str:
        """The file's samples (read once), or why they cannot be used."""
        if path not in self._reads:
            QGuiApplication.setOverrideCursor(Qt.CursorShape.WaitCursor)
            try:
                samples = read_altitude(path)
                self._reads[path] = samples if np.isfinite(samples.altitude_m).any() else (
                    f"{path.name}: no sample holds an altitude; give the altitude another way")
            except InputError as exc:
                self._reads[path] = str(exc)
            finally:
                QGuiApplication.restoreOverrideCursor()
        return self._reads[path]

    def _samples(self) -> AltitudeSamples | None:
        """The chosen file's samples, None for a constant, no file or an unusable file."""
        path = self._chosen_path()
        samples = self._read(path) if path is not None else None
        return samples if isinstance(samples, AltitudeSamples) else None

    def _launch_height_m(self) -> float | None:
        """The launch height typed, None if empty or out of range."""
        value, ok = self._launch_validator.locale().toDouble(self._launch_edit.text())
        low, high = LAUNCH_HEIGHT_RANGE_M
        return value if ok and math.isfinite(value) and low <= value <= high else None

    def _preset_source(self) -> None:
        """Select the altitude source that goes with the choice (SRT → barometer, …)."""
        samples = self._samples()
        kind = ("constant" if self._constant_radio.isChecked()
                else samples.source.kind if samples is not None else None)
        if kind in ALTITUDE_SOURCE_OF_KIND:
            self._source_combo.setCurrentText(ALTITUDE_SOURCE_OF_KIND[kind])

    def _refresh(self) -> None:
        """Enable the fields the choice needs; update the preview, the error and OK."""
        is_constant = self._constant_radio.isChecked()
        path = self._chosen_path()
        read = self._read(path) if path is not None else "Choose an altitude file with Browse…"
        samples = read if isinstance(read, AltitudeSamples) and not is_constant else None
        is_relative = samples is not None and samples.source.is_relative
        self._constant_spin.setEnabled(is_constant)
        self._launch_edit.setEnabled(is_relative)
        self._offset_spin.setEnabled(samples is not None and samples.source.kind == "laser")
        if is_constant:
            self._preview.show_message(
                f"Every frame at {self._constant_spin.value():.2f} m above the water")
        elif samples is not None:
            self._preview.show_message(self._summary(samples))
        else:
            self._preview.show_message(read, "error")
        missing_launch = is_relative and self._launch_height_m() is None
        self._error.show_message(
            f"{samples.source.field} is the height above the take-off point: enter the launch "
            f"height, the take-off point's height above the water "
            f"({LAUNCH_HEIGHT_RANGE_M[0]:g}–{LAUNCH_HEIGHT_RANGE_M[1]:g} m)"
            if missing_launch else "", "error")
        self._problem = self._preview.text() if self._preview.level == "error" else (
            self._error.text())
        self._ok.setEnabled(not self._problem)

    def _summary(self, samples: AltitudeSamples) -> str:
        """One line: field, sample counts, rate, altitude range above the water, gaps."""
        summary = summarize_samples(samples, self._clip.fps)
        launch_m = self._launch_height_m() if samples.source.is_relative else 0.0
        above = "" if launch_m is not None else " above the take-off point"
        family = f" ({samples.source.family})" if samples.source.family else ""
        rate = "rate unknown" if math.isnan(summary.rate_hz) else f"{summary.rate_hz:.3g} Hz"
        gaps = (f"{len(summary.gaps)} gaps, longest {max(g[1] for g in summary.gaps):.1f} s"
                if summary.gaps else "no gaps")
        return (f"{samples.source.field}{family}: {summary.num_samples} samples, "
                f"{summary.num_valid} valid, {rate}, altitude "
                f"{summary.min_altitude_m + (launch_m or 0.0):.2f}–"
                f"{summary.max_altitude_m + (launch_m or 0.0):.2f} m{above}, {gaps}")

    def accept(self) -> None:
        if not self._problem:
            super().accept()

    @property
    def spec(self) -> AltitudeSpec:
        """The chosen altitude; InputError while the dialog shows a problem."""
        if self._problem:
            raise InputError(self._problem)
        source = self._source_combo.currentText()
        if self._constant_radio.isChecked():
            return AltitudeSpec(constant_m=self._constant_spin.value(), source=source)
        samples = self._samples()
        return AltitudeSpec(
            path=relative_media_path(self._project_dir, self._chosen_path()),
            launch_height_m=self._launch_height_m() if samples.source.is_relative else 0.0,
            time_offset_s=(self._offset_spin.value() if samples.source.kind == "laser"
                           else 0.0),
            source=source)
