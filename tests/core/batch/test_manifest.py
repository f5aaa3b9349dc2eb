"""Manifest rows become batch tasks; a bad cell is an error naming the row and column."""

from pathlib import Path

import pytest

from dolphinfit.core.batch.manifest import read_manifest
from dolphinfit.core.batch.task import check_unique_names
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.project.fit_settings import fit_dir
from dolphinfit.core.segment.segmenter import AutoSeed, BoxSeed, PointSeed

HEADER = "clip,animal,altitude,launch_height_m,masks,seed,seed_frame,fps,quality,start_s,end_s"


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    for name in ("a.mp4", "b.mp4", "a.SRT", "alt.csv"):
        (tmp_path / name).write_bytes(b"x")
    (tmp_path / "masks").mkdir()
    return tmp_path


def _manifest(folder: Path, *rows: str, header: str = HEADER) -> Path:
    path = folder / "batch.csv"
    path.write_text("\n".join([header, *rows]) + "\n")
    return path


def test_rows_become_tasks(folder):
    path = _manifest(folder,
                     "a.mp4,left,20.5,1.5,masks,,,2,quick,1,3",
                     "a.mp4,right,,,,\"40,50\",3,,,,",
                     "b.mp4,,alt.csv,,,\"10,20,30,40\",,,thorough,,")
    left, right, b = read_manifest(path, num_draws=100)
    defaults = FitConfig()
    assert (left.fit.altitude, left.fit.launch_height_m) == (20.5, 1.5)
    assert left.fit.masks == folder / "masks"
    assert (left.fit.config.fps, left.fit.config.start_s, left.fit.config.end_s) == (2.0, 1.0, 3.0)
    assert left.fit.config.steps_shape == defaults.steps_shape // 2  # quick: half the steps
    assert left.measurement.altitude_source == "manual" and left.measurement.num_draws == 100
    # an empty altitude is the SRT beside the clip, a barometer altitude
    assert right.fit.altitude is None and right.measurement.altitude_source == "barometer"
    assert right.fit.seed == PointSeed(40.0, 50.0, 3) and right.fit.masks is None
    assert b.fit.altitude == folder / "alt.csv" and b.animal_id == "1"
    assert b.fit.seed == BoxSeed(10, 20, 30, 40, 0)
    assert b.fit.config.steps_shape == defaults.steps_shape * 2
    assert left.name == fit_dir(path, "a.mp4", "left").name != right.name
    assert left.where == f"{path}: row 2"


def test_a_laser_log_is_a_laser_altitude_unless_the_row_says_otherwise(folder):
    """The default altitude source follows the altitude file: a LidarBoX log is a laser."""
    import shutil

    shutil.copy(Path(__file__).parents[2] / "data" / "laser" / "LOG_0007.CSV", folder)
    header = HEADER + ",altitude_source"
    default, stated = read_manifest(_manifest(folder, "a.mp4,1,LOG_0007.CSV,,,,,,,,,",
                                              "b.mp4,1,LOG_0007.CSV,,,,,,,,,barometer",
                                              header=header))
    assert default.measurement.altitude_source == "laser"
    assert stated.measurement.altitude_source == "barometer"


def test_no_masks_and_no_seed_is_the_automatic_seed(folder):
    (task,) = read_manifest(_manifest(folder, "a.mp4,1,20,,,,,,,,"))
    assert task.fit.seed == AutoSeed(0) and task.fit.masks is None


@pytest.mark.parametrize("row, column, why", [
    ("a.mp4,1,0,,,,,,,,", "altitude", "outside the plausible range"),
    ("a.mp4,1,gone.csv,,,,,,,,", "altitude", "neither metres nor an existing file"),
    ("b.mp4,1,,,,,,,,,", "altitude", "no b.SRT"),
    ("a.mp4,1,20,nan,,,,,,,", "launch_height_m", "finite"),
    ("a.mp4,1,20,1.5m,,,,,,,", "launch_height_m", "expected a number"),
    ("a.mp4,1,20,,,\"1,2,3\",,,,,", "seed", "X,Y,W,H"),
    ("a.mp4,1,20,,masks,auto,,,,,", "seed", "not both"),
    ("a.mp4,1,20,,,,-1,,,,", "seed_frame", "must be at least 0"),
    ("a.mp4,1,20,,,,,-2,,,", "fps", "outside the plausible range"),
    ("a.mp4,1,20,,,,,,best,,", "quality", "expected one of"),
    ("a.mp4,1,20,,,,,,,5,2", "start_s", "not before"),
    ("c.mp4,1,20,,,,,,,,", "clip", "does not exist"),
])
def test_bad_cell_names_manifest_row_and_column(folder, row, column, why):
    path = _manifest(folder, "a.mp4,ok,20,,,,,,,,", row)
    with pytest.raises(InputError) as error:
        read_manifest(path)
    assert f"{path}: row 3, column '{column}'" in str(error.value)
    assert why in str(error.value)


@pytest.mark.parametrize("header, rows, message", [
    ("clip,altitude,colour", ["a.mp4,20,red"], "row 1, column 'colour': unknown column"),
    ("animal,altitude", ["1,20"], "row 1, column 'clip': missing"),
    ("clip,animal,altitude", ["a.mp4,1,20", "a.mp4,1,30"],
     "row 3, column 'animal': '1' of a.mp4 is already in row 2"),
    ("clip,animal,altitude", ["a.mp4,1,20,extra"], "row 2: more cells"),
    ("clip,camera", ["a.mp4,no-such-drone"], "row 2, column 'camera'"),
    ("clip,sensor_width_mm", ["a.mp4,17.3"], "row 2, column 'focal_mm': empty"),
    ("clip,animal", [], "no rows"),
])
def test_bad_table_names_row_and_column(folder, header, rows, message):
    path = _manifest(folder, *rows, header=header)
    with pytest.raises(InputError, match=message):
        read_manifest(path)


def test_tasks_sharing_an_output_folder_are_refused(folder):
    path = _manifest(folder, "a.mp4,a b,20,,,,,,,,", "a.mp4,a-b,20,,,,,,,,")
    with pytest.raises(InputError, match=f"{path}: row 3: a.mp4 'a-b' would share the output "
                                         f"folder .* with {path}: row 2"):
        check_unique_names(read_manifest(path))


def test_an_altitude_calibration_is_read_before_any_work(folder):
    """A calibration file is checked when the manifest is read; a good one goes to the fit."""
    from tests.core.measure.test_altitude_calibration import _calibration
    from dolphinfit.core.measure.altitude_calibration import write_altitude_calibration

    write_altitude_calibration(_calibration(), folder / "cal.json")
    (folder / "broken.json").write_text('{"format": "dolphinfit-altitude-calibration"}')
    header = "clip,altitude,altitude_calibration"
    (task,) = read_manifest(_manifest(folder, "a.mp4,20,cal.json", header=header))
    assert task.fit.altitude_calibration == _calibration()
    with pytest.raises(InputError, match="row 2, column 'altitude_calibration': .*broken.json"):
        read_manifest(_manifest(folder, "a.mp4,20,broken.json", header=header))


def _scan(folder: Path, clip_name: str = "a.mp4", usable: bool = True) -> Path:
    from dolphinfit.core.scan.clip_scan import ClipScan
    from dolphinfit.core.scan.frame_scores import FrameScore, ScanSettings
    from dolphinfit.core.scan.scan_files import write_scan_json

    faults = () if usable else ("at the frame's edge",)
    scores = tuple(FrameScore(2, f, f / 10, 100.0 + f, 50.0, 80.0, 2.4, 1.0, 1.0, 1.0, 30.0,
                              20.0, -90.0, 1.0, 1.0, 1.0, q, faults)
                   for f, q in ((10, 0.7), (20, 0.9), (30, 0.8)))
    path = folder / "a_scan.json"
    write_scan_json(path, ClipScan(clip_name, 10.0, 40, 640, 360, (10, 20, 30),
                                   ScanSettings(best_count=2), scores, 1.0))
    return path


def test_a_scan_seeds_the_tracker_and_names_the_frames_to_measure(folder):
    _scan(folder)
    header = "clip,animal,altitude,scan,best"
    (task,) = read_manifest(_manifest(folder, "a.mp4,2,20,a_scan.json,", header=header))
    assert task.fit.seed == PointSeed(120.0, 50.0, 20)  # the best frame's animal
    assert task.measurement.frames == task.fit.also_frames == (20, 30)  # the scan's best 2
    (three,) = read_manifest(_manifest(folder, "a.mp4,2,20,.,3", header=header))  # its folder
    assert three.measurement.frames == (10, 20, 30)


@pytest.mark.parametrize("row, column, why", [
    ("a.mp4,1,20,a_scan.json,,", "animal", "'1' is not an animal of the scan (its animals: 2)"),
    ("a.mp4,2,20,,3,", "best", "needs a scan"),
    ("a.mp4,2,20,a_scan.json,0,", "best", "must be at least 1"),
    ("a.mp4,2,20,a_scan.json,,auto", "seed", "a scan or a tracker seed, not both"),
    ("a.mp4,2,20,gone.json,,", "scan", "does not exist"),
])
def test_bad_scan_cells_name_row_and_column(folder, row, column, why):
    _scan(folder)
    path = _manifest(folder, row, header="clip,animal,altitude,scan,best,seed")
    with pytest.raises(InputError) as error:
        read_manifest(path)
    assert f"{path}: row 2, column '{column}'" in str(error.value) and why in str(error.value)


def test_a_scan_of_another_clip_or_without_usable_frames_is_refused(folder):
    header = "clip,animal,altitude,scan"
    _scan(folder, clip_name="b.mp4")
    with pytest.raises(InputError, match="a_scan.json is the scan of b.mp4, not of a.mp4"):
        read_manifest(_manifest(folder, "a.mp4,2,20,a_scan.json", header=header))
    _scan(folder, usable=False)
    with pytest.raises(InputError, match="no usable frame of animal 2"):
        read_manifest(_manifest(folder, "a.mp4,2,20,a_scan.json", header=header))


def test_a_lens_model_is_read_before_any_work(folder):
    from dolphinfit.core.measure.lens import LensModel, write_lens

    lens = LensModel(1920, 1080, 1400.0, 1400.0, 959.5, 539.5, (-0.1, 0.02, 0.0, 0.0, 0.0),
                     0.05, 9, "boards")
    write_lens(lens, folder / "lens.json")
    (folder / "bad.json").write_text('{"format": "dolphinfit-lens", "version": 1}')
    header = "clip,animal,altitude,lens"
    (task,) = read_manifest(_manifest(folder, "a.mp4,1,20,lens.json", header=header))
    assert task.measurement.lens == lens
    (plain,) = read_manifest(_manifest(folder, "a.mp4,1,20,", header=header))
    assert plain.measurement.lens is None
    path = _manifest(folder, "a.mp4,1,20,bad.json", header=header)
    with pytest.raises(InputError, match=f"{path}: row 2, column 'lens': .*bad.json"):
        read_manifest(path)
