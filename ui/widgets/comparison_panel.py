"""Both methods side by side: length, volume, BCI, density and mass of the elliptical
baseline and of the 3D fit (each with its 95 % interval), their difference in % of the
elliptical value, and a plot of the 19 station widths as the elliptical volume takes them
against the fitted model's, and of the HW-ratio heights against the fitted model's."""

from collections.abc import Sequence

import numpy as np
from matplotlib.backends.backend_qtagg import FigureCanvasQTAgg
from matplotlib.figure import Figure
from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (
    QAbstractItemView, QHeaderView, QLabel, QPushButton, QTableWidget, QTableWidgetItem,
    QVBoxLayout, QWidget,
)

from dolphinfit.core.project.comparison import ComparisonRow

COLUMNS = ("Quantity", "Elliptical (95 %)", "3D fit (95 %)", "Fit − ell.")
FORMATS = {"length_m": ".3f", "volume_m3": ".4f", "bci": "+.3f", "density_kg_m3": ".1f",
           "mass_kg": ".1f"}
PLOT_SIZE_IN = (3.6, 3.4)
PLOT_MIN_HEIGHT_PX = 160


def _cell(text: str) -> QTableWidgetItem:
    item = QTableWidgetItem(text)
    item.setTextAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
    return item


class ComparisonPanel(QWidget):
    """Shows what it is given; the window computes the comparison off the GUI thread.
    ``hw_from_fit_requested``: the user wants the elliptical method to take its HW ratios
    from the fitted model."""

    hw_from_fit_requested = Signal()

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.status = QLabel("No 3D fit yet: start one in the fit panel.", wordWrap=True)
        self.hw_button = QPushButton("Use the fit's HW ratios for the elliptical method",
                                     enabled=False)
        self.hw_button.setToolTip("Heights / widths of the fitted mesh at the 19 stations, "
                                  "saved as a table beside the project, with their source")
        self.hw_button.clicked.connect(self.hw_from_fit_requested)
        self.table = QTableWidget(0, len(COLUMNS))
        self.table.setHorizontalHeaderLabels(COLUMNS)
        self.table.verticalHeader().hide()
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        header = self.table.horizontalHeader()   # the values with their intervals take the room
        header.setSectionResizeMode(QHeaderView.ResizeMode.Stretch)
        for column in (0, len(COLUMNS) - 1):    # the quantities and their differences
            header.setSectionResizeMode(column, QHeaderView.ResizeMode.ResizeToContents)
        self.figure = Figure(figsize=PLOT_SIZE_IN, layout="constrained")
        self.canvas = FigureCanvasQTAgg(self.figure)
        self.canvas.setMinimumHeight(PLOT_MIN_HEIGHT_PX)  # room for both plots, even hidden
        layout = QVBoxLayout(self)
        layout.addWidget(self.status)
        layout.addWidget(self.table)
        layout.addWidget(self.canvas, stretch=1)  # the plot takes the room left
        layout.addWidget(self.hw_button)

    def show_comparison(self, rows: Sequence[ComparisonRow] | None, status: str) -> None:
        """Fill the table and say what the fit is; with ``rows`` None, the table and the
        profiles empty (not another animal's left on show)."""
        self.status.setText(status)
        self.hw_button.setEnabled(rows is not None)
        if rows is None and self.figure.axes:
            self.figure.clear()
            self.canvas.draw_idle()
        rows = list(rows or [])
        self.table.setRowCount(len(rows))
        for i, row in enumerate(rows):
            fmt = FORMATS[row.key]
            label = f"{row.label} ({row.unit})" if row.unit else row.label
            item = QTableWidgetItem(label)
            self.table.setItem(i, 0, item)
            self.table.setItem(i, 1, _cell(row.elliptical.text(fmt)))
            self.table.setItem(i, 2, _cell(row.fitted.text(fmt)))
            self.table.setItem(i, 3, _cell(f"{row.difference:+.1f} %" if row.is_relative
                                           else f"{row.difference:+.3f}"))
        self.table.setFixedHeight(self.table.horizontalHeader().sizeHint().height()
                                  + self.table.verticalHeader().defaultSectionSize()
                                  * max(1, len(rows)) + 4)

    def show_profiles(self, station_pct: np.ndarray, measured_widths_m: np.ndarray | None,
                      used_widths_m: np.ndarray | None, fitted_widths_m: np.ndarray,
                      hw_heights_m: np.ndarray | None, fitted_heights_m: np.ndarray) -> None:
        """Plot widths (the elliptical volume's vs fitted, and measured ones the volume does
        not take, e.g. the flukes' span at 90–95 % with the tail extrapolated) and heights
        (HW-ratio vs fitted) per station."""
        self.figure.clear()
        widths, heights = self.figure.subplots(2, 1, sharex=True)
        for axes, measured, fitted, what, source in (
                (widths, used_widths_m, fitted_widths_m, "width", "elliptical (as used)"),
                (heights, hw_heights_m, fitted_heights_m, "height", "width × HW ratio")):
            if measured is not None:
                axes.plot(station_pct, measured, "o-", ms=3, label=source)
            axes.plot(station_pct, fitted, "s--", ms=3, label="3D fit")
            axes.set_ylabel(f"{what} (m)")
            axes.grid(alpha=0.3)
        if measured_widths_m is not None and used_widths_m is not None:
            unused = np.isfinite(measured_widths_m) & ~np.isclose(measured_widths_m,
                                                                 used_widths_m)
            if unused.any():
                widths.plot(station_pct[unused], measured_widths_m[unused], "x", ms=5,
                            label="measured, not used")
        for axes in (widths, heights):
            axes.legend(fontsize="small")
        heights.set_xlabel("station (% of body length)")
        self.canvas.draw_idle()
