"""CollatriX / Xcertainty wide CSV: column names, calibration columns, union of columns."""

import csv
from pathlib import Path

import pytest

from core.io.collatrix import wide_row, write_wide_csv
from core.io.morphometrix import read_morphometrix

V2_DEMO = Path(__file__).resolve().parents[2] / "data" / "morphometrix" / \
    "mmx_v2_demo-annotated.csv"


def test_row_of_the_v2_demo_has_collatrix_and_xcertainty_columns():
    """TL_m / TL_px, zero-padded widths, angle and areas, and the calibration columns."""
    row = wide_row(read_morphometrix(V2_DEMO), image="demo.csv", altitude_source="laser",
                   image_width_px=6000, sensor_width_mm=23.5, uas="Inspire 2")
    assert (row["Image"], row["Image_ID"], row["Mirror_Side"]) == ("demo.csv", "0000", "None")
    assert (row["Altitude"], row["Focal_Length"], row["Pixel_Dimension"]) == \
        ("50", "50", "0.00391667")
    assert (row["Laser_Alt"], row["Baro_Alt"], row["Launch_Ht"]) == ("50", "", "")
    assert (row["Iw"], row["Sw"], row["uas"]) == ("6000", "23.5", "Inspire 2")
    assert (row["TL_m"], row["TL_px"], row["TL_w10.00_px"], row["TL_w90.00_m"]) == \
        ("7.97", "2034", "152.3", "0.24")
    assert (row["fluke_angle_deg"], row["area_m2"], row["area_px2"]) == \
        ("70.505", "0.026", "1684.5")


def test_barometric_altitude_goes_to_baro_alt():
    """Xcertainty separates altimeters: a barometer reading fills Baro_Alt only."""
    row = wide_row(read_morphometrix(V2_DEMO), image="x", altitude_source="barometer")
    assert (row["Baro_Alt"], row["Laser_Alt"], row["Iw"]) == ("50", "", "")


def test_written_rows_share_the_union_of_their_columns(tmp_path):
    """Rows with different columns are written under all of them; missing cells are empty."""
    record = read_morphometrix(V2_DEMO)
    rows = [wide_row(record, image="a", extras={"volume_m3": 0.25}),
            wide_row(record, image="b", extras={"mass_kg": 240.0})]
    write_wide_csv(tmp_path / "wide.csv", rows)
    with open(tmp_path / "wide.csv", newline="", encoding="utf-8") as file:
        back = list(csv.DictReader(file))
    assert [r["Image"] for r in back] == ["a", "b"]
    assert (back[0]["volume_m3"], back[0]["mass_kg"], back[1]["mass_kg"]) == ("0.25", "", "240")
    assert float(back[1]["TL_px"]) * float(back[1]["Pixel_Dimension"]) == pytest.approx(7.9665,
                                                                                        abs=1e-4)
