"""MorphoMetriX CSVs: the real v1 and v2 files, name normalisation, writing and round trips."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.morphometrix import (
    MorphoMetrixRecord, pixel_measurements, read_morphometrix, record_from_pixels,
    total_length_name, width_name, write_morphometrix, write_morphometrix_v1,
    write_morphometrix_v2,
)
from dolphinfit.core.measure.annotation import PixelMeasurements

DATA = Path(__file__).resolve().parents[2] / "data" / "morphometrix"
V2_DEMO = DATA / "mmx_v2_demo-annotated.csv"
V1_WHALE = DATA / "mmx_v1_Whale1_170816_A_F2_DSC04215.csv"
MINKE = DATA.parent / "real" / "minke"
PERCENTS = [10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0]


def test_v2_demo_metadata_and_scale():
    """The v2 demo: 50 mm, 50 m, 0.00391667 mm/px, so TL 2034.0 px is 7.97 m."""
    record = read_morphometrix(V2_DEMO)
    assert (record.version, record.image_id, record.mirror_side) == (2, "0000", None)
    assert (record.focal_mm, record.altitude_m, record.pixel_dimension_mm) == \
        (50.0, 50.0, 0.00391667)
    assert record.lengths_px["TL"] == 2034.0 and record.lengths_m["TL"] == 7.97
    assert record.lengths_px["TL"] * record.m_per_px == pytest.approx(7.9665, abs=1e-4)
    assert record.focal_px == pytest.approx(12765.9, abs=0.1)


def test_v2_demo_widths_in_pixels_give_its_metres():
    """Width names TL_w10.00 (metres) and TL_w10.0 (pixels) meet; px × scale rounds to the
    metres the file reports (2 decimals)."""
    record = read_morphometrix(V2_DEMO)
    assert sorted(record.widths_m["TL"]) == sorted(record.widths_px["TL"]) == PERCENTS
    assert record.widths_px["TL"][10.0] == 152.3 and record.widths_m["TL"][40.0] == 1.27
    for pct, width_px in record.widths_px["TL"].items():
        assert width_px * record.m_per_px == pytest.approx(record.widths_m["TL"][pct],
                                                            abs=0.005 + 1e-9)
    assert record.lengths_px["fluke"] * record.m_per_px == pytest.approx(1.99, abs=0.005)


def test_v2_demo_angles_and_areas():
    """The angle is kept once; the area in m² and in px² agree through the scale squared."""
    others = {(name, unit): value for name, value, unit in read_morphometrix(V2_DEMO).others}
    assert others == {("fluke_angle", "Degrees"): 70.505, ("area", "Square Meters"): 0.026,
                      ("area", "Square Pixels"): 1684.5}
    assert 1684.5 * 0.00391667**2 == pytest.approx(0.026, abs=5e-4)


def test_v1_whale_blocks():
    """The v1 file: metadata block, TL 24.09 m with nine 10 % widths, Fluke 6.02 m."""
    record = read_morphometrix(V1_WHALE)
    assert (record.version, record.image_id, record.altitude_m) == (1, "Whale1", 85.72)
    assert record.image_path.endswith("170816_A_F2_DSC04215.JPG")
    assert record.lengths_m == {"TL": 24.09, "Fluke": 6.02} and not record.lengths_px
    assert list(record.widths_m["TL"].values()) == [2.48, 3.24, 3.13, 2.8, 2.21, 2.07, 1.52,
                                                    0.94, 0.42]
    assert sorted(record.widths_m["TL"]) == PERCENTS and "Fluke" not in record.widths_m


def test_v1_blocks_headed_object_name_with_nan_cells():
    """MorphoMetriX v1's own demo measurement of its minke image heads its blocks
    ``Object Name,Length,…`` and writes ``nan`` for widths not measured."""
    record = read_morphometrix(MINKE / "test-image.csv")
    assert record.lengths_m == {"Total Length": 7.547, "Fluke_span": 2.225}
    assert record.widths_m["Total Length"][40.0] == 1.257
    assert sorted(record.widths_m["Total Length"]) == PERCENTS
    assert "Fluke_span" not in record.widths_m
    assert record.others == (("Fluke_leadedge", 26.848, "Degrees"),)


def test_v1_pixels_are_derived_from_metres():
    """0.00391667 mm/px × 85.72 m / 50 mm = 6.7147 mm/px: TL 24.09 m is 3587.6 px; the 5 %
    stations the file lacks are NaN."""
    pixels = pixel_measurements(read_morphometrix(V1_WHALE), V1_WHALE)
    assert pixels.length_px == pytest.approx(3587.6, abs=0.05)
    assert pixels.widths_px[1] == pytest.approx(2.48 / 0.0067147390, rel=1e-7)
    assert np.isnan(pixels.widths_px[::2]).all() and not pixels.is_mirrored


def test_round_trip_of_the_real_v2_file(tmp_path):
    """Reading, writing and reading the demo again gives an equal record."""
    record = read_morphometrix(V2_DEMO)
    write_morphometrix_v2(tmp_path / "demo.csv", record)
    assert read_morphometrix(tmp_path / "demo.csv") == record


def test_written_file_has_the_v2_layout(tmp_path):
    """Header, seven metadata rows, zero-padded width names, CRLF line ends."""
    pixels = PixelMeasurements(400.0, np.r_[np.nan, np.linspace(20, 60, 18)], True)
    record = record_from_pixels(pixels, image_id="f1", image_path="clip.mp4", focal_mm=12.29,
                                pixel_dimension_mm=17.27 / 3840, altitude_m=20.0,
                                mirror_side="A")
    path = tmp_path / "out.csv"
    write_morphometrix_v2(path, record)
    lines = path.read_bytes().decode().split("\r\n")
    assert lines[0] == "Object,Value,Value_unit"
    assert lines[6] == "Mirror Side,A,Metadata" and lines[8].startswith("TL,2.92")
    assert lines[9].startswith("TL_w10.00,") and "TL_w05.00" not in path.read_text()
    assert lines[8 + 19].startswith("TL,400,Pixels")


def test_pixels_round_trip_through_a_written_file(tmp_path):
    """Annotation pixels → v2 file → pixels: equal to 10 significant digits (half an ulp of
    the 10th digit, 5e-10), NaN kept."""
    widths = np.linspace(15, 62, 19)
    widths[[4, 17]] = np.nan
    pixels = PixelMeasurements(341.5865663, widths, False)
    record = record_from_pixels(pixels, image_id="x", image_path="", focal_mm=12.29,
                                pixel_dimension_mm=17.27 / 3840, altitude_m=20.0,
                                mirror_side=None)
    write_morphometrix_v2(tmp_path / "x.csv", record)
    back = pixel_measurements(read_morphometrix(tmp_path / "x.csv"), tmp_path / "x.csv")
    assert back.length_px == pytest.approx(pixels.length_px, rel=5e-10)
    np.testing.assert_allclose(back.widths_px, widths, rtol=5e-10)


def test_width_names_are_zero_padded():
    """CollatriX's form: two decimals, padded to two integer digits."""
    assert [width_name("TL", p) for p in (5, 10.0, 95)] == ["TL_w05.00", "TL_w10.00",
                                                            "TL_w95.00"]


def test_off_grid_widths_and_foreign_files_are_input_errors(tmp_path):
    """Widths at 12.5 % cannot feed the 5 % stations; a non-MorphoMetriX CSV is refused."""
    record = MorphoMetrixRecord(2, "i", "", 50.0, 50.0, 0.004, None, "",
                                lengths_px={"TL": 100.0}, widths_px={"TL": {12.5: 10.0}})
    with pytest.raises(InputError, match="TL_w12.50 is not on the 5 % stations"):
        pixel_measurements(record, tmp_path / "r.csv")
    foreign = tmp_path / "foreign.csv"
    foreign.write_text("a,b\n1,2\n", encoding="utf-8")
    with pytest.raises(InputError, match="foreign.csv, line 1: not a MorphoMetriX CSV"):
        read_morphometrix(foreign)
    no_scale = tmp_path / "no_scale.csv"
    no_scale.write_text("Object,Value,Value_unit\nTL,10,Pixels\n", encoding="utf-8")
    with pytest.raises(InputError, match="Focal Length, Altitude, Pixel Dimension missing"):
        read_morphometrix(no_scale)
    bad = tmp_path / "bad.csv"
    bad.write_text("Object,Value,Value_unit\nAltitude,high,Metadata\n", encoding="utf-8")
    with pytest.raises(InputError, match="bad.csv, line 2: Altitude 'high' is not a number"):
        read_morphometrix(bad)


@pytest.mark.parametrize("old, new, message", [
    ("Focal Length,50.0", "Focal Length,0", "line 4: Focal Length: 0 mm is outside"),
    ("Pixel Dimension,0.00391667", "Pixel Dimension,0",
     "line 6: Pixel Dimension: 0 mm/px is outside"),
    ("Altitude,50.0", "Altitude,1e6", r"line 5: Altitude: 1e\+06 m is outside"),
])
def test_impossible_metadata_is_refused_naming_the_line(tmp_path, old, new, message):
    """A zero focal length or pixel size (a ZeroDivisionError before) or a 1000 km altitude."""
    path = tmp_path / "bad.csv"
    path.write_text(V2_DEMO.read_text(encoding="utf-8").replace(old, new), encoding="utf-8")
    with pytest.raises(InputError, match=message):
        read_morphometrix(path)


@pytest.mark.parametrize("old, new, message", [
    ("TL,2034.0,Pixels", "TL,0,Pixels", "TL: body length: 0 m is outside"),
    ("TL_w40.0,325.4,Pixels", "TL_w40.0,2500,Pixels",
     "TL: width 9.792 m is not between 0 and the body length 7.967 m"),
    ("TL_w40.0,325.4,Pixels", "TL_w40.0,-3,Pixels", "TL: width -0.0117"),
])
def test_impossible_lengths_and_widths_are_refused(tmp_path, old, new, message):
    """Zero length, widths beyond the length or negative are InputErrors naming the file."""
    path = tmp_path / "bad.csv"
    path.write_text(V2_DEMO.read_text(encoding="utf-8").replace(old, new), encoding="utf-8")
    with pytest.raises(InputError, match=f"bad.csv: {message}"):
        pixel_measurements(read_morphometrix(path), path)


@pytest.mark.parametrize("name, expected", [
    ("demo-annotated.csv", "Total_Length"), ("test-image.csv", "Total Length")])
def test_total_length_by_its_usual_names(name, expected):
    """Each person named the total length their way; both are found, and read in pixels
    from their metres: 7.593 m and 7.547 m at 3.1781 mm/px."""
    record = read_morphometrix(MINKE / name)
    assert total_length_name(record, MINKE / name) == expected
    assert total_length_name(record, MINKE / name, "total-LENGTH") == expected
    pixels = pixel_measurements(record, MINKE / name)
    assert pixels.length_px * record.m_per_px == pytest.approx(record.lengths_m[expected],
                                                               rel=1e-12)
    assert record.m_per_px == pytest.approx(0.0031781, abs=1e-7)


def test_total_length_missing_or_twice_is_an_input_error(tmp_path):
    """No total length, or TL beside Total_Length: InputError listing the file's lengths."""
    record = MorphoMetrixRecord(1, "i", "", 50.0, 50.0, 0.004, None, "",
                                lengths_m={"Fluke": 2.0})
    with pytest.raises(InputError, match=r"r.csv: no total length .* \(Fluke\); name the"):
        total_length_name(record, tmp_path / "r.csv")
    record = replace(record, lengths_m={"TL": 7.0, "Total_Length": 7.1})
    with pytest.raises(InputError, match=r"several total lengths \(TL, Total_Length\)"):
        total_length_name(record, tmp_path / "r.csv")


def test_v1_round_trip_of_a_persons_file(tmp_path):
    """Their v1 file written again as v1 reads back equal: metadata, lengths, 19 widths, the
    angle and the area."""
    record = read_morphometrix(MINKE / "demo-annotated.csv")
    write_morphometrix(tmp_path / "again.csv", record, version=1)
    assert read_morphometrix(tmp_path / "again.csv") == record
    assert record.others == (("fluke-lead-edge", 23.907, "Degrees"),
                             ("diatom-patch-1", 0.374, "Square Meters"))


def test_pixels_round_trip_through_a_written_v1_file(tmp_path):
    """Annotation pixels → v1 file (metres only) → pixels: equal to 10 significant digits,
    NaN kept; the mirror side has no row in v1."""
    widths = np.linspace(15, 62, 19)
    widths[[4, 17]] = np.nan
    pixels = PixelMeasurements(341.5865663, widths, True)
    record = record_from_pixels(pixels, image_id="x", image_path="", focal_mm=12.29,
                                pixel_dimension_mm=17.27 / 3840, altitude_m=20.0,
                                mirror_side="A")
    write_morphometrix_v1(tmp_path / "x.csv", record)
    back_record = read_morphometrix(tmp_path / "x.csv")
    assert (back_record.version, back_record.mirror_side) == (1, None)
    back = pixel_measurements(back_record, tmp_path / "x.csv")
    assert back.length_px == pytest.approx(pixels.length_px, rel=5e-10)
    np.testing.assert_allclose(back.widths_px, widths, rtol=5e-10)
