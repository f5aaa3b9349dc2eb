"""Tests for core/project/exports.py and core/measure/receipt.py: two animals, three measured
frames."""

import csv
import json
import threading
from dataclasses import replace

import cv2
import numpy as np
import pytest

from dolphinfit.app.cli import main
from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.morphometrix import read_morphometrix
from dolphinfit.core.measure.annotation import place_stations
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.lens import LensModel
from dolphinfit.core.progress import Cancelled
from dolphinfit.core.project import edits
from dolphinfit.core.project.exports import MediaFrames, export_frames
from dolphinfit.core.project.model import (
    Animal, ClipEntry, Measurement, MeasurementKey, Project, get_measurement, with_measurement,
)
from dolphinfit.core.project.results import FrameResult, measure_frame

from .test_calibrations import calibration_set

CAMERA = CameraPreset("test-1080p", "", 8.8, 13.2, 1920, 1080, "test", True)
FRAME_SHAPE = (1080, 1920, 3)
# frame index, midline clicks (px), maximum width (px), stations skipped
FRAMES = {
    ("dolphin 1", 3): (np.array([[300.0, 400.0], [700.0, 460.0], [1100.0, 420.0]]), 140.0, ()),
    ("dolphin 1", 9): (np.array([[320.0, 410.0], [1130.0, 430.0]]), 150.0, (4,)),
    ("dolphin 2", 3): (np.array([[400.0, 800.0], [1000.0, 760.0]]), 110.0, ()),
}


def _measurement(frame_idx: int, midline: np.ndarray, max_width: float,
                 skipped: tuple[int, ...]) -> Measurement:
    """A spindle-shaped dolphin: widths max_width·sin(π·fraction), centred on the midline."""
    widths = max_width * np.sin(np.pi * place_stations(midline).fractions)
    is_skipped = np.zeros(len(widths), bool)
    is_skipped[list(skipped)] = True
    return Measurement(frame_idx, midline, np.stack([widths / 2, -widths / 2], axis=1),
                       is_skipped)


def _project() -> Project:
    animals = tuple(
        Animal(animal_id, measurements=tuple(
            _measurement(frame, *spec) for (owner, frame), spec in FRAMES.items()
            if owner == animal_id))
        for animal_id in ("dolphin 1", "dolphin 2"))
    return Project(clips=(ClipEntry("clips/DJI_0001.MP4", "video", CAMERA, animals=animals),))


def _results(project: Project) -> list[FrameResult]:
    hw = load_hw_preset()
    keys = [MeasurementKey(0, 0, 0), MeasurementKey(0, 0, 1), MeasurementKey(0, 1, 0)]
    return [measure_frame(project, key, 20.0 + key.measurement, "laser", hw, 0) for key in keys]


def _frame(_: FrameResult) -> np.ndarray:
    """A synthetic sea: a smooth dark-blue gradient."""
    ramp = np.linspace(40, 90, FRAME_SHAPE[1], dtype=np.float64)
    frame = np.zeros(FRAME_SHAPE, np.uint8)
    frame[..., 1] = ramp.astype(np.uint8)
    frame[..., 2] = (ramp + 60).astype(np.uint8)
    return frame


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    project = _project()
    results = _results(project)
    out = tmp_path_factory.mktemp("exports")
    calls = []
    paths = export_frames(project, results, out, "survey", frames=_frame,
                          progress=lambda p: calls.append((p.stage, p.step, p.total)))
    return project, results, out, paths, calls


def test_writes_every_file(exported):
    _, _, out, paths, calls = exported
    names = ["DJI_0001_f000003_dolphin-1", "DJI_0001_f000009", "DJI_0001_f000003_dolphin-2"]
    expected = {out / "survey_results.json", out / "survey_wide.csv", out / "survey_collatrix.csv",
                out / "survey_xcertainty.csv",
                *(out / "survey_mmx" / f"{n}.csv" for n in names),
                *(out / "survey_receipts" / f"{n}.png" for n in names),
                *(out / "survey_annotations" / f"{n}.json" for n in names)}
    assert set(paths) == expected and all(p.is_file() for p in paths)
    assert calls == [("write", 1, 3), ("write", 2, 3), ("write", 3, 3)]


def test_wide_csv_rows_match_the_measurements(exported):
    _, _, out, _, _ = exported
    with (out / "survey_wide.csv").open(newline="", encoding="utf-8") as file:
        rows = list(csv.DictReader(file))
    assert len(rows) == 3
    for row, ((animal_id, frame_idx), (midline, max_width, skipped)) in zip(rows, FRAMES.items()):
        stations = place_stations(midline)
        assert (row["clip"], row["animal_id"], row["frame_idx"]) == \
            ("clips/DJI_0001.MP4", animal_id, str(frame_idx))
        assert float(row["TL_px"]) == pytest.approx(stations.length_px, rel=1e-9)
        assert float(row["TL_w05.00_px"]) == pytest.approx(
            max_width * np.sin(np.pi * 0.05), rel=1e-9)
        assert all(row[f"TL_w{5 * (s + 1):05.2f}_px"] == "" for s in skipped)
        assert row["Laser_Alt"] != "" and float(row["volume_m3"]) > 0


def test_collatrix_table_tells_two_animals_on_one_frame_apart(exported):
    """CollatriX joins and sums on (Image_ID, Image): Image is the clip's base name, Image_ID
    the export name, unique even where two animals share frame 3."""
    _, results, out, _, _ = exported
    with (out / "survey_collatrix.csv").open(newline="", encoding="utf-8") as file:
        rows = list(csv.DictReader(file))
    assert [(r["Image"], r["Image_ID"], r["csv"]) for r in rows] == [
        ("DJI_0001.MP4", name, f"{name}.csv") for name in
        ("DJI_0001_f000003_dolphin-1", "DJI_0001_f000009", "DJI_0001_f000003_dolphin-2")]
    assert [r["Filled_Widths"] for r in rows] == ["", "25", ""]
    assert float(rows[2]["TL"]) == pytest.approx(float(results[2].estimate.point.length_m))


def test_mmx_files_read_back_with_the_same_length(exported):
    _, results, out, _, _ = exported
    for path, result in zip(sorted((out / "survey_mmx").glob("*.csv")),
                            sorted(results, key=lambda r: (r.image_id, r.key.animal))):
        record = read_morphometrix(path)
        assert record.lengths_px["TL"] == pytest.approx(result.source.pixels.length_px,
                                                        rel=1e-9)


def test_json_summarises_each_animal(exported):
    _, results, out, _, _ = exported
    data = json.loads((out / "survey_results.json").read_text(encoding="utf-8"))
    assert data["schema_version"] == 1 and len(data["frames"]) == 3
    frame = data["frames"]["DJI_0001_f000009"]
    assert (frame["animal_id"], frame["frame_idx"]) == ("dolphin 1", 9)
    assert frame["result"]["volume_m3"] == pytest.approx(results[1].record["volume_m3"])
    first, second = data["animals"]
    assert first["frames"] == ["DJI_0001_f000003_dolphin-1", "DJI_0001_f000009"]
    for key in ("length_m", "volume_m3", "bci", "mass_kg"):
        values = [r.record[key] for r in results[:2]]
        assert first["summary"][key]["mean"] == pytest.approx(np.mean(values), rel=1e-12)
        assert first["summary"][key]["sd"] == pytest.approx(np.std(values, ddof=1), rel=1e-9)
    assert second["summary"]["length_m"]["n"] == 1 and second["summary"]["length_m"]["sd"] is None


def test_edge_sources_go_to_the_wide_csv_and_the_json(tmp_path):
    """Each width edge's source is a wide-CSV column and a station entry of the result JSON;
    the CollatriX and MorphoMetriX files keep their layouts."""
    project, key = _project(), MeasurementKey(0, 0, 0)
    m = get_measurement(project, key)
    stations = edits.stations_of(m)
    same_edges = stations.points_px[:, None] + m.offsets_px[..., None] * stations.normals[:, None]
    m = edits.offsets_from_edges(m, same_edges, only_missing=False)
    m = edits.set_offset(edits.move_offset(m, 1, 0, m.offsets_px[1, 0] + 2.0), 2, 1,
                         m.offsets_px[2, 1])
    project = with_measurement(project, key, edits.set_skipped(m, 4, True))
    export_frames(project, _results(project)[:1], tmp_path, "s")
    with (tmp_path / "s_wide.csv").open(newline="", encoding="utf-8") as file:
        row = next(csv.DictReader(file))
    assert [row[f"TL_w{pct}_{side}_source"] for pct in ("05.00", "10.00", "15.00", "25.00")
            for side in "AB"] == ["suggested", "suggested", "suggested_moved", "suggested",
                                  "suggested", "clicked", "", ""]  # 25 %: skipped
    result = json.loads((tmp_path / "s_results.json").read_text(encoding="utf-8"))
    stations = result["frames"]["DJI_0001_f000003"]["result"]["stations"]
    assert (stations[1]["side_a_source"], stations[2]["side_b_source"]) == \
        ("suggested_moved", "clicked")
    assert stations[4]["side_a_source"] is None
    with (tmp_path / "s_collatrix.csv").open(newline="", encoding="utf-8") as file:
        columns = next(csv.reader(file))
    assert not any(column.endswith(("_A_source", "_B_source")) for column in columns)
    assert "suggested" not in (tmp_path / "s_mmx" / "DJI_0001_f000003.csv").read_text()


def _measured_by_cli(annotation, out_dir, *options) -> dict:
    """`dolphinfit measure ANNOTATION` without draws: its result JSON."""
    assert main(["measure", str(annotation), "--mc", "0", "--out", str(out_dir), *options]) == 0
    return json.loads((out_dir / f"{annotation.stem}_measure.json").read_text(encoding="utf-8"))


def test_annotations_measure_as_in_the_app(exported, tmp_path, capsys):
    """`dolphinfit measure` on each exported annotation gives the app's length and volume."""
    _, results, out, _, _ = exported
    for name, result in zip(["DJI_0001_f000003_dolphin-1", "DJI_0001_f000009",
                             "DJI_0001_f000003_dolphin-2"], results):
        measured = _measured_by_cli(out / "survey_annotations" / f"{name}.json", tmp_path)
        for key in ("length_m", "volume_m3"):
            assert measured[key] == pytest.approx(result.record[key], rel=1e-12)
    capsys.readouterr()


def test_annotation_carries_the_lens_and_the_media_path(tmp_path, capsys):
    """A clip with a lens model: its lens goes beside the annotation, the media path is
    relative to the annotation, and with --lens and the project's --tail the CLI agrees."""
    lens = LensModel(1920, 1080, 1280.0, 1280.0, 959.5, 539.5, (-0.2, 0.05, 0.0, 0.0, 0.0),
                     0.1, 9, "test")
    base = _project()
    project = Project(clips=(replace(base.clips[0], lens=lens),), tail="measured")
    key = MeasurementKey(0, 0, 1)
    result = measure_frame(project, key, 21.0, "laser", load_hw_preset(), 0)
    paths = export_frames(project, [result], tmp_path / "out", "s",
                          project_dir=tmp_path / "project")
    annotation = tmp_path / "out" / "s_annotations" / "DJI_0001_f000009.json"
    lens_file = tmp_path / "out" / "s_lenses" / "DJI_0001_f000009.json"
    assert {annotation, lens_file} <= set(paths)
    data = json.loads(annotation.read_text(encoding="utf-8"))
    assert data["image"]["media_path"] == "../../project/clips/DJI_0001.MP4"
    assert data["altitude"] == {"altitude_m": 21.0, "source": "laser"}
    measured = _measured_by_cli(annotation, tmp_path, "--lens", str(lens_file),
                                "--tail", "measured")
    for key_name in ("length_m", "volume_m3"):
        assert measured[key_name] == pytest.approx(result.record[key_name], rel=1e-12)
    as_clicked = _measured_by_cli(annotation, tmp_path, "--tail", "measured")
    assert as_clicked["length_m"] != pytest.approx(result.record["length_m"], rel=1e-6)
    capsys.readouterr()


def test_annotation_carries_the_altitude_calibration(tmp_path, capsys):
    """A clip whose altitudes are calibrated: the annotation keeps the recorded altitude, the
    calibration goes beside it, and with --altitude-calibration the CLI agrees."""
    base = _project()
    project = replace(base, calibrations=(calibration_set(CAMERA),), clips=(
        replace(base.clips[0], altitude_calibration="test drone barometer"),))
    result = measure_frame(project, MeasurementKey(0, 1, 0), 22.0, "barometer",
                           load_hw_preset(), 0)
    assert result.record["altitude_m"] != pytest.approx(22.0)  # corrected in the app
    export_frames(project, [result], tmp_path, "s")
    annotation = tmp_path / "s_annotations" / "DJI_0001_f000003.json"
    assert json.loads(annotation.read_text(encoding="utf-8"))["altitude"]["altitude_m"] == 22.0
    measured = _measured_by_cli(annotation, tmp_path, "--altitude-calibration",
                                str(tmp_path / "s_altitude_calibrations" / annotation.name))
    for key in ("length_m", "volume_m3"):
        assert measured[key] == pytest.approx(result.record[key], rel=1e-12)
    capsys.readouterr()


def test_receipt_draws_along_the_midline(exported):
    _, _, out, _, _ = exported
    receipt = cv2.cvtColor(cv2.imread(str(out / "survey_receipts" / "DJI_0001_f000009.png")),
                           cv2.COLOR_BGR2RGB)
    frame = _frame(None)
    assert receipt.shape == frame.shape
    midline = FRAMES[("dolphin 1", 9)][0]
    for t in np.linspace(0.2, 0.8, 7):  # points on the straight midline, clear of the caption
        u, v = np.round(midline[0] + t * (midline[1] - midline[0])).astype(int)
        assert np.abs(receipt[v, u].astype(int) - frame[v, u]).sum() > 60
    assert np.array_equal(receipt[-20:, -20:], frame[-20:, -20:])  # untouched far away


def test_nothing_to_export_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="nothing to export"):
        export_frames(_project(), [], tmp_path, "empty")


def test_cancel_removes_what_was_written(tmp_path):
    project = _project()
    cancel = threading.Event()
    with pytest.raises(Cancelled):
        export_frames(project, _results(project), tmp_path, "cut", frames=_frame,
                      progress=lambda _: cancel.set(), cancel=cancel)
    assert list(tmp_path.iterdir()) == []


def test_media_frames_reads_each_clip_once_and_notes_missing_media(tmp_path):
    frame = _frame(None)
    cv2.imwrite(str(tmp_path / "still.png"), cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
    measurement = _measurement(0, *FRAMES[("dolphin 2", 3)])
    clips = tuple(ClipEntry(name, "image", CAMERA, animals=(Animal("d", measurements=(
        measurement,)),)) for name in ("still.png", "gone.png"))
    project = Project(clips=clips)
    hw = load_hw_preset()
    results = [measure_frame(project, MeasurementKey(c, 0, 0), 20.0, "laser", hw, 0)
               for c in (0, 1)]
    with MediaFrames(project, tmp_path / "survey.dolphinfit") as frames:
        assert np.array_equal(frames(results[0]), frame)
        assert frames(results[1]) is None and frames(results[1]) is None
    assert len(frames.notes) == 1 and frames.notes[0].startswith("gone.png frame 0: no receipt")
