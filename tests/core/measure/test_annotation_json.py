"""Annotation JSON files: round trips, calibration kept apart, atomic writes, clear errors."""

import copy
import json

import numpy as np
import pytest

from dolphinfit.core.camera_presets import CameraPreset, get_preset
from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation_json import (
    AnnotationFile, annotation_from_json, annotation_to_json, read_annotation_json,
    write_annotation_json,
)
from dolphinfit.core.measure.annotation import Annotation, Calibration, pixel_measurements

MIDLINE = np.array([[100.0, 400.0], [300.0, 420.0], [520.0, 410.0]])


def _edges():
    """Edge points 20 px either side of a horizontal midline at u = 110, 130, …"""
    u = 100.0 + 21 * np.arange(1, 20)
    edges = np.stack([np.stack([u, np.full(19, 390.0)], 1),
                      np.stack([u, np.full(19, 430.0)], 1)], axis=1)
    edges[3] = np.nan  # skipped
    return edges


def _doc(mirror_side=None, preset=True):
    camera = (get_preset("dji-mavic3-4k") if preset else
              CameraPreset("explicit", "", 8.8, 13.2, 3840, 2160, "test", False))
    calibration = Calibration(camera, camera.name if preset else None, 21.5, "barometer")
    edges = _edges()
    if mirror_side == "A":
        edges[:, 1] = np.nan
    return AnnotationFile(Annotation(1234, MIDLINE, edges, mirror_side), calibration,
                          image_id="DJI_0042 f1234", media_path="DJI_0042.MP4", notes="flat")


@pytest.mark.parametrize("mirror_side, preset", [(None, True), ("A", False)])
def test_round_trip_keeps_pixels_and_calibration(tmp_path, mirror_side, preset):
    """Write then read gives the same clicks, edges, frame, camera, altitude and metadata."""
    doc = _doc(mirror_side, preset)
    path = tmp_path / "a" / "frame.json"
    write_annotation_json(path, doc)
    back = read_annotation_json(path)
    np.testing.assert_array_equal(back.annotation.midline_px, MIDLINE)
    np.testing.assert_array_equal(back.annotation.edges_px, doc.annotation.edges_px)
    assert back.annotation.mirror_side == mirror_side and back.annotation.frame_idx == 1234
    assert back.calibration.preset_name == doc.calibration.preset_name
    for key in ("focal_mm", "sensor_width_mm", "image_width_px", "image_height_px"):
        assert getattr(back.calibration.camera, key) == getattr(doc.calibration.camera, key)
    assert (back.calibration.altitude_m, back.calibration.altitude_source) == (21.5, "barometer")
    assert (back.image_id, back.media_path, back.notes) == ("DJI_0042 f1234", "DJI_0042.MP4",
                                                            "flat")
    assert [p.name for p in path.parent.iterdir()] == ["frame.json"]  # no temporary left


def test_file_stores_the_preset_by_name_and_skipped_stations_explicitly():
    """The camera is a preset reference; a skipped station is {"skipped": true}."""
    data = annotation_to_json(_doc())
    assert data["camera"] == {"preset": "dji-mavic3-4k"}
    assert data["altitude"] == {"altitude_m": 21.5, "source": "barometer"}
    assert data["stations"][3] == {"station_pct": 20.0, "skipped": True}
    assert data["stations"][0]["side_a_px"] == [121.0, 390.0]


def test_a_corrected_altitude_rescales_without_touching_the_pixels():
    """Editing only the altitude scales metres per pixel; the pixel measurements stay."""
    data = annotation_to_json(_doc())
    changed = copy.deepcopy(data)
    changed["altitude"]["altitude_m"] = 25.8
    before, after = (annotation_from_json(d, "test") for d in (data, changed))
    assert after.calibration.m_per_px / before.calibration.m_per_px == pytest.approx(1.2)
    a, b = pixel_measurements(before.annotation), pixel_measurements(after.annotation)
    assert a.length_px == b.length_px
    np.testing.assert_array_equal(a.widths_px, b.widths_px)


def _mutated(change):
    data = annotation_to_json(_doc())
    change(data)
    return data


@pytest.mark.parametrize("change, message", [
    (lambda d: d.update(schema_version=2), "schema_version 2 was written by a newer dolphinfit"),
    (lambda d: d.update(extra=1), "unknown keys \\['extra'\\]"),
    (lambda d: d.update(camera={"preset": "dji-nope"}), "unknown camera preset 'dji-nope'"),
    (lambda d: d.update(camera={"focal_mm": 8.8}), "expected {'preset': NAME}"),
    (lambda d: d["altitude"].update(source="gps"),
     "altitude source 'gps' is not one of laser, barometer, manual"),
    (lambda d: d["altitude"].update(altitude_m=-3),
     "altitude_m: -3 m is outside the plausible range 1–500 m"),
    (lambda d: d["altitude"].update(altitude_m=1e6), r"altitude_m: 1e\+06 m is outside"),
    (lambda d: d.update(midline_px=[[0, 0]]), "N ≥ 2"),
    (lambda d: d["midline_px"].__setitem__(1, [1, "x"]), "midline_px\\[1\\]: expected \\[u, v\\]"),
    (lambda d: d["stations"][4].update(side_b_px=None), "stations\\[4\\] \\(25 %\\): side_b_px"),
    (lambda d: d["stations"][5].update(station_pct=35), "stations\\[5\\]: station_pct 35"),
    (lambda d: d["stations"].pop(), "list of the 19 stations"),
    (lambda d: d["image"].update(frame_idx=True), "'frame_idx' has the wrong type"),
    # a point nobody could click: outside the image, or huge
    (lambda d: d["midline_px"].__setitem__(1, [1e12, 360.0]),
     r"midline_px\[1\] \(1e\+12, 360\) lies outside the \d+×\d+ image"),
    (lambda d: d["stations"][9].update(side_a_px=[300.0, -2.0]),
     r"stations \(50 %\) side_a_px \(300, -2\) lies outside"),
])
def test_bad_files_raise_input_errors_naming_the_entry(change, message):
    """Each malformed entry raises InputError whose message says where and what."""
    with pytest.raises(InputError, match=message):
        annotation_from_json(_mutated(change), "frame.json")


def test_unreadable_files_name_the_path(tmp_path):
    """A missing file and invalid JSON raise InputError naming the file."""
    with pytest.raises(InputError, match="missing.json: cannot read"):
        read_annotation_json(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{", encoding="utf-8")
    with pytest.raises(InputError, match="bad.json: not valid JSON"):
        read_annotation_json(bad)
    bad.write_text(json.dumps([1]), encoding="utf-8")
    with pytest.raises(InputError, match="expected a JSON object"):
        read_annotation_json(bad)
