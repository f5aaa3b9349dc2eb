"""A calibration table's drone, video mode, object length and camera, and the camera preset its
drone and video mode name."""

from pathlib import Path

import pandas as pd
import pytest

from dolphinfit.core.camera_presets import (
    CameraPreset,
    load_presets,
    preset_for_drone,
    table_camera,
)
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.calibration_table import read_calibration_table

MEDIDOR_CALIB = Path(__file__).resolve().parents[2] / "data" / "real" / "medidor" / "calib.xlsx"
AIR2 = CameraPreset("my-air2", "DJI Mavic Air 2, 2.7K video 2688x1512", 7.6, 6.4, 2688, 1512,
                    "test", False)


@pytest.fixture(autouse=True)
def no_user_presets(tmp_path, monkeypatch):
    monkeypatch.setenv("DOLPHINFIT_CONFIG_DIR", str(tmp_path / "config"))


def _with_columns(tmp_path: Path, **columns) -> Path:
    path = tmp_path / "calib.csv"
    pd.read_excel(MEDIDOR_CALIB).assign(**columns).to_csv(path, index=False)
    return path


def test_medidor_sheet_names_drone_video_mode_and_object_but_no_camera():
    """calib.xlsx: 351 shots of a 202 cm object by a Mavic Air 2 at 2.7k, no camera columns;
    no bundled preset is that camera."""
    table = read_calibration_table(MEDIDOR_CALIB)
    assert (len(table.shots), table.drone, table.resolution) == (351, "Mavic Air 2", "2.7k")
    assert table.common_value("object_length_m") == pytest.approx(2.02)
    assert table.common_value("focal_mm") is None
    assert table_camera(table, load_presets()) is None
    camera, origin = table_camera(table, {**load_presets(), AIR2.name: AIR2})
    assert camera == AIR2 and origin == "preset 'my-air2': calib.xlsx names Mavic Air 2 at 2.7k"


def test_camera_columns_give_the_camera_and_disagreeing_rows_are_refused(tmp_path):
    """flen, sw, iw state the camera (focal px 3192, as the CLI's options); only part of them
    states none; rows that differ are an error naming the file."""
    camera, origin = table_camera(read_calibration_table(
        _with_columns(tmp_path, flen=7.6, sw=6.4, iw=2688)), {})
    assert (camera.focal_mm, camera.sensor_width_mm, camera.image_width_px) == (7.6, 6.4, 2688)
    assert camera.intrinsics().focal_px == pytest.approx(3192.0)
    assert (camera.name, origin) == ("Mavic Air 2", "calib.csv's columns")
    assert table_camera(read_calibration_table(_with_columns(tmp_path, flen=7.6)),
                        {AIR2.name: AIR2}) is None
    frame = pd.read_excel(MEDIDOR_CALIB)
    frame.assign(flen=[7.6] * 350 + [8.0], sw=6.4, iw=2688).to_csv(tmp_path / "x.csv",
                                                                    index=False)
    with pytest.raises(InputError, match=r"x\.csv: the rows disagree on focal_mm \(7\.6, 8\)"):
        table_camera(read_calibration_table(tmp_path / "x.csv"), {})


@pytest.mark.parametrize("drone, mode, expected", [
    ("Mavic 3", "2.7k", "dji-mavic3-2.7k"),        # the name without its maker and mode
    ("DJI Mavic 3", "5.1K", "dji-mavic3-5.1k"),
    ("Mavic 3", "FHD", "dji-mavic3-fhd"),
    ("Mavic 3", "4k", None),                       # DCI 4K and 4K UHD: two cameras
    ("Mavic", "2.7k", None),                       # another drone's name in part
    ("Phantom 4", "4k", None),                     # not the Phantom 4 Pro
    ("Phantom 4 Pro", "4K", "dji-phantom4pro-4k"),
    ("Mavic 3", "", None),
])
def test_a_drone_and_video_mode_name_one_bundled_preset_or_none(drone, mode, expected):
    found = preset_for_drone(drone, mode, load_presets())
    assert (found.name if found else None) == expected


def test_a_longer_model_name_is_another_drone():
    """A preset of the Mavic Air 2S is not the Mavic Air 2's."""
    air2s = CameraPreset("dji-mavic-air2s-2.7k", "DJI Mavic Air 2S, 2.7K video", 8.4, 13.2,
                         2688, 1512, "test", False)
    assert preset_for_drone("Mavic Air 2", "2.7k", {air2s.name: air2s}) is None
    assert preset_for_drone("Mavic Air 2S", "2.7k", {air2s.name: air2s}) == air2s
