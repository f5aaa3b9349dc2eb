"""The fit panel of the current animal: what to fit (frame range, frames per second, quality,
refraction, crops), Start and Cancel, and while the fit runs its stage, step, ETA, mean IoU
and a small plot of the loss. It only shows and asks; the window runs the fit in a worker."""

import math

from PySide6.QtCore import QPointF, Qt, Signal
from PySide6.QtGui import QColor, QPainter, QPaintEvent, QPen, QPolygonF
from PySide6.QtWidgets import (
    QCheckBox, QComboBox, QDoubleSpinBox, QFormLayout, QHBoxLayout, QLabel, QProgressBar,
    QPushButton, QVBoxLayout, QWidget,
)

from dolphinfit.core.progress import Progress
from dolphinfit.core.project.fit_settings import QUALITY_STEP_SCALE, FitSettings

LOSS_PLOT_HEIGHT_PX = 60
MAX_FPS = 30.0


def format_eta(eta_s: float | None) -> str:
    """"ETA 1 min 05 s", or "" before there is a rate."""
    if eta_s is None:
        return ""
    minutes, seconds = divmod(round(eta_s), 60)
    return f"ETA {minutes} min {seconds:02d} s" if minutes else f"ETA {seconds} s"


class LossPlot(QWidget):
    """The fit's total loss per step on a log scale (a sparkline; new points append)."""

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setFixedHeight(LOSS_PLOT_HEIGHT_PX)
        self.values: list[float] = []
        self.setToolTip("Total loss per optimisation step (log scale)")

    def clear(self) -> None:
        self.values = []
        self.update()

    def add(self, value: float) -> None:
        if math.isfinite(value) and value > 0:
            self.values.append(value)
            self.update()

    def paintEvent(self, event: QPaintEvent) -> None:  # noqa: N802 (Qt's name)
        painter = QPainter(self)
        painter.fillRect(self.rect(), QColor("#202428"))
        if len(self.values) < 2:
            return
        logs = [math.log10(v) for v in self.values]
        low, high = min(logs), max(logs)
        span = high - low or 1.0
        w, h = self.width() - 4, self.height() - 4
        points = [QPointF(2 + w * i / (len(logs) - 1), 2 + h * (high - value) / span)
                  for i, value in enumerate(logs)]
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)
        painter.setPen(QPen(QColor("#7fd1ff"), 1.5))
        painter.drawPolyline(QPolygonF(points))
        painter.setPen(QColor("#c8c8c8"))
        painter.drawText(self.rect().adjusted(4, 2, -4, -2),
                         Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignTop,
                         f"loss {self.values[-1]:.3g}")


class FitPanel(QWidget):
    """Settings, Start/Cancel and progress of the current animal's fit."""

    start_requested = Signal(object)     # FitSettings
    cancel_requested = Signal()
    settings_changed = Signal(object)    # FitSettings, as the user edits them
    range_typed = Signal(object)         # FitSettings, at each keystroke in the range or rate

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.start_s = self._seconds("from the start")
        self.end_s = self._seconds("to the end")
        self.fps = QDoubleSpinBox(decimals=1, minimum=0.5, maximum=MAX_FPS, singleStep=0.5,
                                  suffix=" frames/s")
        self.quality = QComboBox()
        for name in QUALITY_STEP_SCALE:
            self.quality.addItem(name, name)
        self.refraction = QCheckBox("refraction at the water surface")
        self.roi = QCheckBox("native-resolution crops around the animal")
        form = QFormLayout()
        form.addRow("From (s):", self.start_s)
        form.addRow("To (s):", self.end_s)
        form.addRow("Fit:", self.fps)
        form.addRow("Quality:", self.quality)
        form.addRow(self.refraction)
        form.addRow(self.roi)
        self.mask_note = QLabel(wordWrap=True, visible=False)  # the range's masks
        self.start_button = QPushButton("Start fit")
        self.cancel_button = QPushButton("Cancel", enabled=False)
        buttons = QHBoxLayout()
        buttons.addWidget(self.start_button)
        buttons.addWidget(self.cancel_button)
        self.progress_bar = QProgressBar(textVisible=True)
        self.progress_label = QLabel(wordWrap=True)
        self.loss_plot = LossPlot()
        self.status = QLabel("Measure the animal, then fit the 3D model to the clip.",
                             wordWrap=True)
        layout = QVBoxLayout(self)
        layout.addLayout(form)
        layout.addWidget(self.mask_note)
        layout.addLayout(buttons)
        for widget in (self.progress_bar, self.progress_label, self.loss_plot, self.status):
            layout.addWidget(widget)
        layout.addStretch(1)
        self.start_button.clicked.connect(self._on_start)
        self.cancel_button.clicked.connect(self.cancel_requested)
        for box in (self.start_s, self.end_s, self.fps):
            box.editingFinished.connect(self._on_edited)
            box.valueChanged.connect(self._on_typed)
        self.quality.currentIndexChanged.connect(self._on_edited)
        for check in (self.refraction, self.roi):
            check.toggled.connect(self._on_edited)
        self._last_step = -1
        self._running = False
        self._can_start = True  # the range's masks allow a fit (show_mask_check)
        self.set_settings(FitSettings(), None)

    @staticmethod
    def _seconds(open_end: str) -> QDoubleSpinBox:
        box = QDoubleSpinBox(decimals=2, minimum=-0.01, maximum=1e6, singleStep=1.0,
                             suffix=" s")
        box.setSpecialValueText(open_end)  # shown at the minimum: no bound
        return box

    def set_settings(self, settings: FitSettings, duration_s: float | None) -> None:
        """Show an animal's settings; ``duration_s`` bounds the range (None: unknown)."""
        widgets = (self.start_s, self.end_s, self.fps, self.quality, self.refraction, self.roi)
        for widget in widgets:
            widget.blockSignals(True)
        for box, value in ((self.start_s, settings.start_s), (self.end_s, settings.end_s)):
            if duration_s is not None:
                box.setMaximum(duration_s)
            box.setValue(box.minimum() if value is None else value)
        self.fps.setValue(settings.fps)
        self.quality.setCurrentIndex(self.quality.findData(settings.quality))
        self.refraction.setChecked(settings.refraction)
        self.roi.setChecked(settings.roi)
        for widget in widgets:
            widget.blockSignals(False)

    def settings(self) -> FitSettings:
        """The settings shown (ValueError when they contradict each other)."""
        def bound(box: QDoubleSpinBox) -> float | None:
            return None if box.value() <= box.minimum() else box.value()

        return FitSettings(start_s=bound(self.start_s), end_s=bound(self.end_s),
                           fps=self.fps.value(), quality=self.quality.currentData(),
                           refraction=self.refraction.isChecked(), roi=self.roi.isChecked())

    def _valid_settings(self) -> FitSettings | None:
        """The settings shown, or None after saying in the panel why they are not valid."""
        try:
            return self.settings()
        except ValueError as exc:
            self.status.setText(f"⚠ {exc}")
            return None

    def _on_edited(self) -> None:
        if (settings := self._valid_settings()) is not None:
            self.settings_changed.emit(settings)

    def _on_typed(self) -> None:
        try:
            self.range_typed.emit(self.settings())
        except ValueError:
            pass  # half typed: said when the edit ends (_on_edited)

    def _on_start(self) -> None:
        if (settings := self._valid_settings()) is not None:
            self.start_requested.emit(settings)

    def show_mask_check(self, note: str, can_start: bool) -> None:
        """What the range's masks allow: ``note`` above Start ("" for none), and Start only
        if ``can_start``."""
        self._can_start = can_start
        self.mask_note.setText(note)
        self.mask_note.setVisible(bool(note))
        self.start_button.setEnabled(can_start and not self._running)
        self.start_button.setToolTip("" if can_start else note)

    def set_running(self, running: bool) -> None:
        """Lock the settings while a fit runs; Cancel only then."""
        self._running = running
        for widget in (self.start_s, self.end_s, self.fps, self.quality, self.refraction,
                       self.roi):
            widget.setEnabled(not running)
        self.start_button.setEnabled(not running and self._can_start)
        self.cancel_button.setEnabled(running)
        if running:
            self._last_step = -1
            self.loss_plot.clear()
            self.progress_bar.setValue(0)
            self.status.setText("Fitting…")

    def show_progress(self, progress: Progress) -> None:
        """Stage, step of total, ETA, mean IoU and the loss."""
        self.progress_bar.setMaximum(max(1, progress.total))
        self.progress_bar.setValue(progress.step)
        self.progress_bar.setFormat(f"{progress.stage}: step %v / %m")
        parts = [progress.stage, f"step {progress.step} / {progress.total}",
                 format_eta(progress.eta_s)]
        if "mean_iou" in progress.metrics:
            parts.append(f"mean IoU {progress.metrics['mean_iou']:.3f}")
        self.progress_label.setText(" · ".join(p for p in parts if p))
        if "total" in progress.metrics and progress.step > self._last_step:
            self.loss_plot.add(float(progress.metrics["total"]))  # once per step, not per heartbeat
        self._last_step = max(self._last_step, progress.step)

    def show_status(self, text: str) -> None:
        """What became of the fit, in words."""
        self.status.setText(text)
