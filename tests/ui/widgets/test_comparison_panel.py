"""The comparison panel shows both methods' numbers with units and plots the profiles."""

import numpy as np

from dolphinfit.core.measure.stations import STATION_PCT
from dolphinfit.core.project.comparison import ComparisonRow, MethodValue
from dolphinfit.ui.widgets.comparison_panel import ComparisonPanel


def test_table_and_profiles(qtbot):
    panel = ComparisonPanel()
    qtbot.addWidget(panel)
    rows = [ComparisonRow("volume_m3", "Volume", "m³", MethodValue(0.2, 0.15, 0.26),
                          MethodValue(0.23, 0.19, 0.27)),
            ComparisonRow("bci", "BCI", "", MethodValue(0.1), MethodValue(0.12))]
    panel.show_comparison(rows, "3D fit: complete, mean IoU 0.91")
    assert panel.table.rowCount() == 2
    assert panel.table.item(0, 0).text() == "Volume (m³)"
    assert panel.table.item(0, 1).text() == "0.2000 (0.1500–0.2600)"
    assert panel.table.item(0, 2).text() == "0.2300 (0.1900–0.2700)"
    assert panel.table.item(0, 3).text() == "+15.0 %"
    assert panel.table.item(1, 1).text() == "+0.100"  # no interval: value only
    assert panel.table.item(1, 2).text() == "+0.120"
    assert panel.table.item(1, 3).text() == "+0.020"  # BCI: a difference, not a % of it
    widths = 0.4 * np.sin(np.pi * STATION_PCT / 100)
    measured = widths.copy()
    measured[-2:] = (0.35, 0.5)  # the flukes' span, which an extrapolated tail leaves out
    panel.show_profiles(STATION_PCT, measured, widths, widths * 1.05, None, widths * 1.2)
    top, bottom = panel.figure.axes
    assert len(top.lines) == 3 and len(bottom.lines) == 1
    assert top.get_ylabel() == "width (m)"
    np.testing.assert_allclose(top.lines[0].get_ydata(), widths)
    np.testing.assert_allclose(top.lines[1].get_ydata(), widths * 1.05)
    np.testing.assert_allclose(top.lines[2].get_xdata(), STATION_PCT[-2:])
    assert top.lines[2].get_label() == "measured, not used"
    panel.show_profiles(STATION_PCT, widths, widths, widths * 1.05, None, widths * 1.2)
    assert len(panel.figure.axes[0].lines) == 2  # every measured width used: no extra marks
    panel.show_comparison(None, "No 3D fit yet")
    assert panel.table.rowCount() == 0
    assert panel.figure.axes == []   # another animal's profiles are not left on show
