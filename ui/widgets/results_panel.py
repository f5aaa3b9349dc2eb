"""The results of the current measured frame (values, 95 % intervals, station widths, warnings),
the elliptical settings, and the current animal's mean, SD and range over its frames.

The panel observes the ProjectModel: every change sends a new request to its ResultsWorker,
so the numbers follow a dragged handle (nominal values within milliseconds, the interval once
the drag pauses). It computes nothing itself; the window gives it the altitude of a frame.
"""

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (
    QAbstractItemView, QComboBox, QFormLayout, QGridLayout, QGroupBox, QHeaderView, QLabel,
    QScrollArea, QTableWidget, QTableWidgetItem, QVBoxLayout, QWidget,
)

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation import SIDES
from dolphinfit.core.measure.baseline import BaselineEstimate
from dolphinfit.core.measure.edge_sources import (
    EDGE_CLICKED, EDGE_SUGGESTED, EDGE_SUGGESTED_MOVED,
)
from dolphinfit.core.measure.elliptical import TAIL_EXTRAPOLATED, TAIL_IDX, TAIL_MEASURED
from dolphinfit.core.measure.hw_ratios import preset_names
from dolphinfit.core.measure.stations import NUM_STATIONS, STATION_PCT
from dolphinfit.core.measure.uncertainty import Summary
from dolphinfit.core.project.comparison import interval_of
from dolphinfit.core.project.model import Measurement
from dolphinfit.core.project.results import FrameResult, LengthResult, Spread
from dolphinfit.ui.state.commands import push_edit
from dolphinfit.ui.state.project_model import Change, ProjectModel
from dolphinfit.ui.workers.results_worker import AnimalSummary, ResultsWorker

AltitudeLookup = Callable[[int, int], tuple[float, str]]  # (clip, frame) → (m, source)

# result key, label with unit, format
FRAME_ROWS = (("length_m", "Length (m)", ".3f"), ("volume_m3", "Volume (m³)", ".4f"),
              ("bci", "BCI", "+.3f"), ("density_kg_m3", "Density (kg/m³)", ".1f"),
              ("mass_kg", "Mass (kg)", ".1f"))
ANIMAL_ROWS = tuple(row for row in FRAME_ROWS if row[0] != "density_kg_m3")
TAIL_LABELS = {TAIL_EXTRAPOLATED: "from 85 % (CollatriX)", TAIL_MEASURED: "as measured"}
EDGE_SOURCE_TEXT = {EDGE_CLICKED: "measured", EDGE_SUGGESTED: "suggested",
                    EDGE_SUGGESTED_MOVED: "suggested, moved"}  # "Width from"
PENDING, NONE = "…", "—"
PROBLEM_COLOUR, HINT_COLOUR = "#b00020", "#505050"
STATION_ROWS_VISIBLE = 10
RIGHT = Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter


def _number_label() -> QLabel:
    label = QLabel(NONE)
    label.setAlignment(RIGHT)
    label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
    return label


def _range_text(low: float, high: float, fmt: str) -> str:
    return f"{format(low, fmt)} – {format(high, fmt)}"


def _edges_text(measurement: Measurement, idx: int) -> str:
    """How a measured station's edges were placed: one phrase, or one per side where the
    sides differ ("A suggested / B measured")."""
    sides = measurement.needed_sides()
    texts = [EDGE_SOURCE_TEXT[measurement.edge_sources[idx, side]] for side in sides]
    if len(set(texts)) == 1:
        return texts[0]
    return " / ".join(f"{SIDES[side]} {text}" for side, text in zip(sides, texts))


def _station_state(estimate: BaselineEstimate, measurement: Measurement, idx: int) -> str:
    """How a station's width was obtained, in words."""
    if estimate.settings.tail == TAIL_EXTRAPOLATED and idx in TAIL_IDX:
        return "from 85 %"
    if np.isfinite(estimate.measured.widths_px[idx]):
        return _edges_text(measurement, idx)
    return "skipped, filled" if measurement.skipped[idx] else "filled"


class ResultsPanel(QWidget):
    """Results of the current frame and animal; ``result_shown`` after every update."""

    result_shown = Signal(object)  # the FrameResult now shown
    animal_figures = Signal(object)  # {MeasurementKey: "length, volume"} of the animal's frames

    def __init__(self, model: ProjectModel, worker: ResultsWorker | None = None,
                 parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._model = model
        self.worker = worker or ResultsWorker(parent=self)
        self._lookup: AltitudeLookup | None = None
        self._request_id = self._animal_request_id = -1
        self._requested: tuple[Measurement, str] | None = None  # measurement, altitude source
        self._result: FrameResult | None = None
        self._preset_names = preset_names()

        self.message = QLabel(wordWrap=True)
        self.values: dict[str, QLabel] = {}
        self.intervals: dict[str, QLabel] = {}
        self.warnings = QLabel(wordWrap=True)
        self.hw_combo = QComboBox()
        self.tail_combo = QComboBox()
        for option, text in TAIL_LABELS.items():
            self.tail_combo.addItem(text, option)
        self.stations = self._station_table()
        self.animal_title = QLabel(wordWrap=True)
        self.animal_cells: dict[tuple[str, str], QLabel] = {}

        content = QWidget()
        layout = QVBoxLayout(content)
        layout.addWidget(self.message)
        layout.addWidget(self._frame_box())
        layout.addWidget(self.warnings)
        layout.addWidget(self._settings_box())
        layout.addWidget(self.stations)
        layout.addWidget(self._animal_box())
        layout.addStretch(1)
        scroll = QScrollArea(widgetResizable=True)
        scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        scroll.setWidget(content)
        outer = QVBoxLayout(self)
        outer.setContentsMargins(0, 0, 0, 0)
        outer.addWidget(scroll)

        self.hw_combo.currentIndexChanged.connect(self._on_hw_chosen)
        self.tail_combo.currentIndexChanged.connect(self._on_tail_chosen)
        self.worker.nominal_ready.connect(self._on_result)
        self.worker.interval_ready.connect(self._on_result)
        self.worker.failed.connect(self._on_failed)
        self.worker.animal_ready.connect(self._on_animal)
        model.changed.connect(self.refresh)
        model.selection_changed.connect(self.refresh)
        model.path_changed.connect(self._on_path_changed)
        self._on_path_changed()
        self.refresh()

    # ----- public
    def set_altitude_lookup(self, lookup: AltitudeLookup | None) -> None:
        """The altitude (m, source) of a clip's frame; raises InputError when there is none."""
        self._lookup = lookup
        self.refresh()

    def current_result(self) -> FrameResult | None:
        """The FrameResult shown, None when none is."""
        return self._result

    def shutdown(self) -> None:
        """Stop the worker thread (the window's close)."""
        self.worker.shutdown()

    # ----- layout
    def _frame_box(self) -> QGroupBox:
        box = QGroupBox("Current frame")
        grid = QGridLayout(box)
        grid.addWidget(QLabel("95 % interval"), 0, 2, RIGHT)
        rows = [("frame", "Frame"), ("altitude_m", "Altitude (m)"),
                ("altitude_source", "Altitude source"), ("gsd", "GSD (cm/px)")]
        rows += [(key, text) for key, text, _ in FRAME_ROWS]
        for row, (key, text) in enumerate(rows, start=1):
            grid.addWidget(QLabel(text), row, 0)
            self.values[key] = _number_label()
            grid.addWidget(self.values[key], row, 1)
            if key in {k for k, _, _ in FRAME_ROWS}:
                self.intervals[key] = _number_label()
                grid.addWidget(self.intervals[key], row, 2)
        grid.setColumnStretch(2, 1)
        return box

    def _settings_box(self) -> QGroupBox:
        box = QGroupBox("Elliptical volume")
        form = QFormLayout(box)
        form.setRowWrapPolicy(QFormLayout.RowWrapPolicy.WrapLongRows)
        form.addRow("HW ratios", self.hw_combo)
        form.addRow("90/95 % widths", self.tail_combo)
        return box

    def _station_table(self) -> QTableWidget:
        table = QTableWidget(NUM_STATIONS, 3)
        table.setHorizontalHeaderLabels(["Station (%)", "Width (m)", "Width from"])
        table.verticalHeader().hide()
        table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        table.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeMode.Stretch)
        for row, pct in enumerate(STATION_PCT):
            table.setItem(row, 0, self._cell(f"{pct:g}"))
        table.verticalHeader().setDefaultSectionSize(table.fontMetrics().height() + 6)
        height = table.verticalHeader().defaultSectionSize() * STATION_ROWS_VISIBLE
        table.setFixedHeight(height + table.horizontalHeader().sizeHint().height() + 4)
        return table

    def _animal_box(self) -> QGroupBox:
        box = QGroupBox("Animal over its frames")
        grid = QGridLayout(box)
        grid.addWidget(self.animal_title, 0, 0, 1, 4)
        for col, head in enumerate(("Mean", "SD", "Range"), start=1):
            grid.addWidget(QLabel(head), 1, col, RIGHT)
        for row, (key, text, _) in enumerate(ANIMAL_ROWS, start=2):
            grid.addWidget(QLabel(text), row, 0)
            for col, stat in enumerate(("mean", "sd", "range"), start=1):
                self.animal_cells[key, stat] = _number_label()
                grid.addWidget(self.animal_cells[key, stat], row, col)
        grid.setColumnStretch(3, 1)
        return box

    @staticmethod
    def _cell(text: str) -> QTableWidgetItem:
        item = QTableWidgetItem(text)
        item.setTextAlignment(RIGHT)
        return item

    # ----- requests
    def refresh(self, change: Change | None = None) -> None:
        """Ask for the current frame's and animal's results (and sync the settings)."""
        if change is None or change.kind == "settings":
            self._sync_settings()
        model, key = self._model, self._model.current_key()
        if model.animal_idx is not None:
            self._request_animal(model.clip_idx, model.animal_idx)
        else:
            self._animal_request_id = -1
            self._show_animal([], None)
        if key is None:
            self._clear("Select a measured frame to see its results.")
            return
        measurement = model.current_measurement()
        try:
            altitude_m, source = self._altitude(key.clip, measurement.frame_idx)
        except InputError as exc:
            self._clear(str(exc))
            return
        self._requested = (measurement, source)
        self._request_id = self.worker.request(model.project, key, altitude_m, source)

    def _altitude(self, clip_idx: int, frame_idx: int) -> tuple[float, str]:
        if self._lookup is None:
            raise InputError("no altitude for this clip: set one (Clip → Altitude…)")
        return self._lookup(clip_idx, frame_idx)

    def _request_animal(self, clip_idx: int, animal_idx: int) -> None:
        altitudes = {}
        for measurement in self._model.project.clips[clip_idx].animals[animal_idx].measurements:
            try:
                altitudes[measurement.frame_idx] = self._altitude(clip_idx, measurement.frame_idx)
            except InputError:
                continue  # left out, and counted by the worker
        self._animal_request_id = self.worker.request_animal(
            self._model.project, clip_idx, animal_idx, altitudes)

    # ----- settings
    def _on_path_changed(self) -> None:
        path = self._model.path
        self.worker.project_dir = None if path is None else path.parent

    def _sync_settings(self) -> None:
        """Show the project's HW table and tail option without pushing an edit."""
        project = self._model.project
        extra = [] if project.hw_ratios in self._preset_names else [project.hw_ratios]
        for combo in (self.hw_combo, self.tail_combo):
            combo.blockSignals(True)
        self.hw_combo.clear()
        self.hw_combo.addItems(self._preset_names + extra)  # extra: a CSV file or the 3D model
        self.hw_combo.setCurrentText(project.hw_ratios)
        self.tail_combo.setCurrentIndex(self.tail_combo.findData(project.tail))
        for combo in (self.hw_combo, self.tail_combo):
            combo.blockSignals(False)

    def _on_hw_chosen(self, index: int) -> None:
        self._push_setting("hw_ratios", self.hw_combo.itemText(index), "HW ratios")

    def _on_tail_chosen(self, index: int) -> None:
        self._push_setting("tail", self.tail_combo.itemData(index), "tail option")

    def _push_setting(self, name: str, value: str, what: str) -> None:
        project = self._model.project
        if getattr(project, name) != value:
            push_edit(self._model, replace(project, **{name: value}), f"{what}: {value}",
                      Change("settings"))

    # ----- results
    def _on_result(self, request_id: int, result: FrameResult | LengthResult) -> None:
        if request_id != self._request_id:
            return
        if isinstance(result, LengthResult):
            self._show_length(result)
            return
        self._result = result
        measurement = self._requested[0]
        estimate, record = result.estimate, result.record
        self._set_message("")
        self._show_frame(record["altitude_m"], estimate.m_per_px)
        for key, _, fmt in FRAME_ROWS:
            self._show_value(key, record[key], interval_of(estimate, key), fmt)
        for row in range(NUM_STATIONS):
            self.stations.setItem(row, 1, self._cell(f"{estimate.point.widths_m[row]:.3f}"))
            self.stations.setItem(row, 2, self._cell(_station_state(estimate, measurement, row)))
        # a number and its unit stay on one line ("25 %", not "25" | "%")
        self.warnings.setText("\n".join(f"⚠ {text}".replace(" %", "\u00a0%")
                                        for text in record["warnings"]))
        self.result_shown.emit(result)

    def _show_frame(self, altitude_m: float, m_per_px: float) -> None:
        """The frame, its altitude and its ground sampling distance."""
        measurement, source = self._requested
        self.values["frame"].setText(str(measurement.frame_idx))
        self.values["altitude_m"].setText(f"{altitude_m:.2f}")
        self.values["altitude_source"].setText(source)
        self.values["gsd"].setText(f"{m_per_px * 100:.3f}")

    def _show_length(self, result: LengthResult) -> None:
        """A frame with a length and no width yet: its length and interval, the rest
        waiting for the widths."""
        self._result = None
        self._blank()
        self._set_message("Volume, BCI and mass follow once a width is placed.",
                          is_problem=False)
        self._show_frame(result.altitude_m, result.m_per_px)
        key, _, fmt = FRAME_ROWS[0]
        self._show_value(key, result.length_m, result.interval, fmt)

    def _show_value(self, key: str, value: float, summary: Summary | None, fmt: str) -> None:
        """A figure, and its interval (with mean and SD as a tooltip) or that it is coming."""
        self.values[key].setText(format(value, fmt))
        self.intervals[key].setText(PENDING if summary is None else
                                    _range_text(float(summary.low), float(summary.high), fmt))
        self.intervals[key].setToolTip("" if summary is None else
                                       f"mean {format(float(summary.mean), fmt)}, "
                                       f"SD {format(float(summary.sd), fmt.lstrip('+'))}")

    def _on_failed(self, request_id: int, message: str) -> None:
        if request_id == self._request_id:
            self._clear(message)

    def _clear(self, message: str) -> None:
        """No result to show, and why."""
        self.worker.cancel()
        self._request_id = -1
        self._result = None
        self._set_message(message)
        self._blank()

    def _blank(self) -> None:
        """Every figure and station cell empty."""
        for label in (*self.values.values(), *self.intervals.values()):
            label.setText(NONE)
            label.setToolTip("")
        for row in range(NUM_STATIONS):
            for col in (1, 2):
                self.stations.setItem(row, col, self._cell(""))
        self.warnings.setText("")

    def _set_message(self, text: str, is_problem: bool = True) -> None:
        """Why figures are missing: in red when something is wrong, else a plain hint."""
        self.message.setStyleSheet(f"color: {PROBLEM_COLOUR if is_problem else HINT_COLOUR};")
        self.message.setText(text)
        self.message.setVisible(bool(text))

    def _on_animal(self, results: list[FrameResult], summary: AnimalSummary) -> None:
        if summary.request_id == self._animal_request_id:
            self._show_animal(results, summary)
            self.animal_figures.emit({r.key: f"{r.record['length_m']:.2f} m, "
                                             f"{r.record['volume_m3']:.3f} m³" for r in results})

    def _show_animal(self, results: list[FrameResult], summary: AnimalSummary | None) -> None:
        spreads: dict[str, Spread] = summary.spreads if summary is not None else {}
        if summary is None:
            self.animal_title.setText("No animal selected.")
        else:
            left = (f"; {summary.num_left_out} not measurable yet"
                    if summary.num_left_out else "")
            self.animal_title.setText(f"{summary.animal_id}: n = {len(results)} "
                                      f"frame{'s' if len(results) != 1 else ''}{left}")
        for key, _, fmt in ANIMAL_ROWS:
            spread = spreads.get(key)
            texts = {"mean": NONE, "sd": NONE, "range": NONE} if spread is None else {
                "mean": format(spread.mean, fmt),
                "sd": NONE if np.isnan(spread.sd) else format(spread.sd, fmt.lstrip("+")),
                "range": _range_text(spread.low, spread.high, fmt)}
            for stat, text in texts.items():
                self.animal_cells[key, stat].setText(text)
