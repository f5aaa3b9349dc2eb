"""MedidoR's measurement spreadsheet: the real file its GUI test writes, and bad input."""

from pathlib import Path

import openpyxl
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.medidor import read_medidor

SHEET = Path(__file__).parents[2] / "data" / "real" / "medidor" / "Measurements_10.xlsx"


def test_reads_the_sheet_of_medidors_gui_test():
    """Both rows (the test saves twice): 2.7K Mavic Air 2 at 22.5 + 0.5 m, BL 1171.56 px,
    9 widths, the fluke span and the metres per pixel it applied."""
    rows = read_medidor(SHEET)
    assert len(rows) == 2
    row = rows[0]
    assert (row.image_id, row.image_name) == ("RW-1", "example_whale.png")
    assert (row.altitude_m, row.sensor_width_mm, row.image_width_px, row.focal_mm) == \
        (23, 6.4, 2688, 7.6)
    assert row.length_px == pytest.approx(1171.55663356342, abs=1e-9)
    assert list(row.widths_px) == [10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0]
    assert row.widths_px[40.0] == pytest.approx(265.0846845821162, abs=1e-9)
    assert row.fluke_span_px == pytest.approx(467.5823029157542, abs=1e-9)
    assert row.length_px * row.gsd_m_per_px == pytest.approx(13.74777755533639, abs=1e-9)


def _sheet(path: Path, header: list[str], row: list[object]) -> Path:
    workbook = openpyxl.Workbook()
    workbook.active.append(header)
    workbook.active.append(row)
    workbook.save(path)
    return path


HEADER = ["ID", "imid", "BL", "C_Alt", "sw", "iw", "flen", "cGSD", "WD_10"]


@pytest.mark.parametrize("header, row, message", [
    (HEADER[:-1], ["a", "b", 1, 20, 6.4, 2688, 4.5, 0.01], "no width columns"),
    (HEADER[1:], ["b", 1, 20, 6.4, 2688, 4.5, 0.01, 3], "no column ID"),
    (HEADER, ["a", "b", "long", 20, 6.4, 2688, 4.5, 0.01, 3], "row 2: BL 'long' is not"),
    (HEADER, ["a", "b", 100, -20, 6.4, 2688, 4.5, 0.01, 3], "row 2: C_Alt must be a positive number"),
    (HEADER, ["a", "b", 100, 20, 6.4, 2688, None, 0.01, 3], "row 2: flen must be a positive number"),
])
def test_bad_sheets_are_refused_naming_the_file_row_and_column(tmp_path, header, row, message):
    path = _sheet(tmp_path / "m.xlsx", header, row)
    with pytest.raises(InputError, match=message.replace("(", r"\(")) as caught:
        read_medidor(path)
    assert str(path) in str(caught.value)


def test_a_file_that_is_no_workbook_is_refused(tmp_path):
    path = tmp_path / "m.xlsx"
    path.write_text("BL,WD_10\n1,2\n")
    with pytest.raises(InputError, match="cannot be read as an .xlsx workbook"):
        read_medidor(path)
    with pytest.raises(InputError, match="no such file"):
        read_medidor(tmp_path / "missing.xlsx")
