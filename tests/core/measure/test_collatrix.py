"""CollatriX and wide tables: column names, calibration columns, union of columns, and both
tables read by a copy of CollatriX's body-condition column logic."""

import csv
import math
from dataclasses import replace
from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest

from dolphinfit.core.measure.collatrix import collatrix_row, wide_row, write_wide_csv
from dolphinfit.core.measure.morphometrix import read_morphometrix
from dolphinfit.core.measure.baseline import BaselineSettings, estimate_baseline
from dolphinfit.core.measure.elliptical import TAIL_EXTRAPOLATED
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.records import (
    collatrix_csv_row, default_error_model, measured_image_from_morphometrix, result_record,
    wide_csv_row,
)

DATA = Path(__file__).resolve().parents[2] / "data" / "morphometrix"
V2_DEMO = DATA / "mmx_v2_demo-annotated.csv"
V1_WHALE = DATA / "mmx_v1_Whale1_170816_A_F2_DSC04215.csv"  # TL 24.09 m, widths every 10 %


def _collatrix_bv_ellipse(rows: list[dict[str, str]], tl: str = "TL") -> dict[tuple, float]:
    """CollatriX v2's elliptical body volume (``bv_ellipse``), rewritten from its behaviour:
    heights are ``{tl}_w{pct:.2f}`` × ``{tl}_ratio{pct:.2f}`` at 5…85 % (a missing column is
    a KeyError), 90 % and 95 % are ⅔ and ⅓ of 85 %, 0 % and 100 % are zero; the width
    columns are then collected by substring, in station order, heights named by replacing
    "w" with "h"; each 5 % segment is integrated by the trapezoid rule in 100 steps. Returns
    BVell_5perc per (Image_ID, Image), summed over rows sharing them."""
    volumes: dict[tuple, float] = {}
    for raw in rows:
        row: dict[str, float | str] = dict(raw)
        for pct in range(5, 90, 5):
            w = f"{tl}_w{pct:.2f}"
            row[w.replace("w", "h")] = float(row[w]) * float(row[w.replace("w", "ratio")])
        w85, h85 = float(row[f"{tl}_w85.00"]), row[f"{tl}_h85.00"]
        for pct, keep in ((90, 2 / 3), (95, 1 / 3), (0, 0.0), (100, 0.0)):
            row[f"{tl}_w{pct:.2f}"], row[f"{tl}_h{pct:.2f}"] = keep * w85, keep * h85
        names = [f"{tl}_w{pct:.2f}" for pct in range(0, 105, 5)]
        widths = [column for name in names for column in row if name in column]
        heights = [column.replace("w", "h") for column in widths]
        step = float(row[tl]) * 5 / 100
        total = 0.0
        for (w1, w2), (h1, h2) in zip(pairwise(widths), pairwise(heights)):
            a, b, c, d = (float(row[k]) for k in (w1, w2, h1, h2))
            x = np.linspace(0.0, 1.0, 101)
            area = math.pi * (a + (b - a) * x) / 2 * (c + (d - c) * x) / 2
            total += float(np.sum((area[1:] + area[:-1]) / 2) / 100) * step
        key = (raw["Image_ID"], raw["Image"])
        volumes[key] = volumes.get(key, 0.0) + total
    return volumes


def _write_and_read(path: Path, row: dict[str, str]) -> list[dict[str, str]]:
    write_wide_csv(path, [row])
    with open(path, newline="", encoding="utf-8") as file:
        return list(csv.DictReader(file))


@pytest.fixture(scope="module")
def whale():
    """The real v1 file measured with the provisional HW table and CollatriX's tail."""
    source = measured_image_from_morphometrix(V1_WHALE)
    errors = default_error_model(source.altitude_source, False)
    estimate = estimate_baseline(source.pixels, source.focal_px, source.record.altitude_m,
                                 BaselineSettings(load_hw_preset(), TAIL_EXTRAPOLATED), errors,
                                 0, np.random.default_rng(0))
    return source, estimate, result_record(source, estimate, input_name="w", seed=0)


def test_collatrix_reads_our_collatrix_table_and_gets_our_volume(whale, tmp_path):
    """CollatriX's logic on the written CollatriX table of the real whale: every column it
    needs is there, no width is matched twice, and its BVell_5perc is our volume (its 100-step
    trapezoid is within 2e-6 of the exact frustums)."""
    source, estimate, result = whale
    rows = _write_and_read(tmp_path / "w_collatrix.csv",
                           collatrix_csv_row(source, estimate, csv_name="w_mmx.csv"))
    ((key, volume),) = _collatrix_bv_ellipse(rows).items()
    assert key == ("Whale1", "170816_A_F2_DSC04215.JPG")
    assert volume == pytest.approx(result["volume_m3"], rel=2e-6)
    assert result["volume_m3"] == pytest.approx(106.3098, abs=1e-4)
    row = rows[0]
    assert list(row)[:10] == ["csv", "Image", "Image_ID", "Image_Path", "Altitude",
                              "Focal_Length", "Pixel_Dimension", "Mirror_Side", "Notes",
                              "metadata_source"]
    assert (row["csv"], row["TL"], row["TL_w10.00"], row["TL_w90.00"]) == \
        ("w_mmx.csv", "24.09", "2.48", "0.42")
    assert float(row["TL_w5.00"]) == pytest.approx(2.48 / 2, rel=1e-9)  # filled, not measured
    assert row["Filled_Widths"] == "5 15 25 35 45 55 65 75 85 95"
    assert not [c for c in row if c.endswith("_px") or c == "BVell_5perc"]


def test_collatrix_cannot_read_the_wide_table(whale, tmp_path):
    """Our wide table names the length TL_m and pads the 5 % width (TL_w05.00_m, as CollatriX's
    own collation does): its body-condition step finds no TL_w5.00, and widths found by
    substring would come twice (_m and _px). Hence the separate CollatriX table."""
    source, estimate, result = whale
    rows = _write_and_read(tmp_path / "w_wide.csv",
                           wide_csv_row(source, estimate, result, csv_name="w_mmx.csv"))
    with pytest.raises(KeyError, match="TL_w5.00"):
        _collatrix_bv_ellipse(rows)
    assert [c for c in rows[0] if "TL_w10.00" in c] == ["TL_w10.00_m", "TL_w10.00_px"]
    assert (rows[0]["Image"], rows[0]["TL_m"], rows[0]["BVell_5perc"]) == \
        ("170816_A_F2_DSC04215.JPG", "24.09", f"{result['volume_m3']:.10g}")


def test_collatrix_row_of_the_v2_demo_is_metres_under_bare_names():
    """Lengths, angles and square metres under their own names, pixels nowhere; ``Image`` the
    base name of a POSIX or Windows image path; HW ratios at 5…85 %, the ones CollatriX
    reads."""
    record = read_morphometrix(V2_DEMO)
    ratios = {pct: 1.0 + pct / 100 for pct in range(5, 100, 5)}
    row = collatrix_row(record, csv_name="demo.csv", hw_ratios=ratios)
    assert (row["Image"], row["Image_ID"], row["metadata_source"]) == \
        ("demo.png", "0000", "mmx_input")
    assert (row["TL"], row["TL_w10.00"], row["fluke"], row["fluke_angle"], row["area"]) == \
        ("7.97", "0.6", "1.99", "70.505", "0.026")
    assert [c for c in row if "ratio" in c] == [f"TL_ratio{p}.00" for p in range(5, 90, 5)]
    assert row["TL_ratio85.00"] == "1.85" and row["Filled_Widths"] == ""
    assert not [c for c in row if "px" in c or c.endswith(("_m", "_m2", "_deg"))]
    windows = replace(record, image_path="D:\\survey\\F2\\DSC04215.JPG")
    assert collatrix_row(windows, csv_name="x", hw_ratios=ratios)["Image"] == "DSC04215.JPG"
    nameless = replace(record, image_path="")
    assert collatrix_row(nameless, csv_name="x.csv", hw_ratios=ratios)["Image"] == "x.csv"


def test_row_of_the_v2_demo_has_collatrix_and_xcertainty_columns():
    """TL_m / TL_px, zero-padded widths, angle and areas, and the calibration columns."""
    row = wide_row(read_morphometrix(V2_DEMO), csv_name="demo.csv", altitude_source="laser",
                   image_width_px=6000, sensor_width_mm=23.5, uas="Inspire 2")
    assert (row["csv"], row["Image_ID"], row["Mirror_Side"]) == ("demo.csv", "0000", "None")
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
    row = wide_row(read_morphometrix(V2_DEMO), csv_name="x", altitude_source="barometer")
    assert (row["Baro_Alt"], row["Laser_Alt"], row["Iw"]) == ("50", "", "")


def test_written_rows_share_the_union_of_their_columns(tmp_path):
    """Rows with different columns are written under all of them; missing cells are empty."""
    record = read_morphometrix(V2_DEMO)
    rows = [wide_row(record, csv_name="a", extras={"volume_m3": 0.25}),
            wide_row(record, csv_name="b", extras={"mass_kg": 240.0})]
    write_wide_csv(tmp_path / "wide.csv", rows)
    with open(tmp_path / "wide.csv", newline="", encoding="utf-8") as file:
        back = list(csv.DictReader(file))
    assert [r["csv"] for r in back] == ["a", "b"]
    assert (back[0]["volume_m3"], back[0]["mass_kg"], back[1]["mass_kg"]) == ("0.25", "", "240")
    assert float(back[1]["TL_px"]) * float(back[1]["Pixel_Dimension"]) == pytest.approx(7.9665,
                                                                                        abs=1e-4)
