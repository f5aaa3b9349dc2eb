"""A still's own camera: the real minke photograph's from its EXIF and the sensor table, the
focal-plane tags where written, and a still of no known camera refused until one is set."""

from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.media import open_media
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.project.evaluate import all_keys, frame_results
from dolphinfit.core.project.model import (
    CAMERA_UNKNOWN, AltitudeSpec, Animal, MeasurementKey, Project,
)
from dolphinfit.core.project.new_project import clip_entry_for
from dolphinfit.core.project.photo_camera import load_sensor_table, photo_camera
from dolphinfit.core.project.project_file import read_project, write_project
from dolphinfit.core.project.results import measure_frame, measure_length

from ..io.exif_still import write_still
from .conftest import ellipse_measurement

MINKE = Path(__file__).parents[2] / "data" / "real" / "minke" / "demo.JPG"
MINKE_SIZE = (2978, 1985)            # a crop of the camera's 6000 × 4000 frame
MORPHOMETRIX_PIXEL_MM = 0.00391667   # the pixel size its authors measured the minke with
MINKE_ALTITUDE_M = 28.4


def test_the_minke_photographs_camera_is_its_sony_at_the_sony_pixel_size():
    """23.5 mm / 6000 px = 3.9167 µm, kept by the crop; 35 mm / 0.0039167 mm = 8936 px; at
    28.4 m one pixel is 3.18 mm on the water (the video preset gave 13.4 mm)."""
    camera, note = photo_camera(MINKE, *MINKE_SIZE)
    assert note == camera.description == (
        "from the photo's EXIF: SONY ILCE-5100, 35 mm, pixel 3.92 µm")
    assert camera.focal_mm == 35.0 and camera.approximate
    pixel_mm = camera.sensor_width_mm / camera.image_width_px
    assert pixel_mm == pytest.approx(23.5 / 6000, rel=1e-12)
    assert pixel_mm == pytest.approx(MORPHOMETRIX_PIXEL_MM, rel=1e-5)
    intrinsics = camera.intrinsics()
    assert intrinsics.focal_px == pytest.approx(35 / MORPHOMETRIX_PIXEL_MM, rel=1e-5)
    gsd_mm = intrinsics.gsd_m_per_px(MINKE_ALTITUDE_M) * 1000
    assert gsd_mm == pytest.approx(3.18, rel=0.005)
    assert "Sony α5100" in camera.source


def test_focal_plane_tags_win_over_the_sensor_table(tmp_path):
    path = write_still(tmp_path / "p.jpg", np.zeros((400, 600, 3), np.uint8), 35.0, 0.004,
                       make="SONY", model="ILCE-5100")
    camera, _ = photo_camera(path, 600, 400)
    assert camera.sensor_width_mm == pytest.approx(0.004 * 600, rel=1e-6)
    assert "focal-plane" in camera.source


def test_no_pixel_size_for_a_resized_photo_or_an_unknown_model(tmp_path):
    rgb = np.zeros((40, 60, 3), np.uint8)
    sony = write_still(tmp_path / "sony.jpg", rgb, 35.0, make="SONY", model="ILCE-5100")
    camera, why = photo_camera(sony, 7000, 4000)
    assert camera is None and "wider than the 6000 px SONY ILCE-5100 writes" in why
    other = write_still(tmp_path / "other.jpg", rgb, 8.0, make="ACME", model="X1")
    camera, why = photo_camera(other, 60, 40)
    assert camera is None and "ACME X1 is not in the sensor table" in why


def test_every_sensor_table_entry_names_its_source():
    table = load_sensor_table()
    assert table["ilce-5100"].pixel_mm == pytest.approx(MORPHOMETRIX_PIXEL_MM, rel=1e-5)
    assert all(entry.source.strip() for entry in table.values())


def _unknown_camera_project(tmp_path: Path) -> tuple[Project, Path]:
    """A measured still whose EXIF names no camera, at a constant altitude, saved."""
    still = tmp_path / "still.png"
    cv2.imwrite(str(still), np.zeros((720, 1280, 3), np.uint8))
    with open_media(still) as source:
        entry, note = clip_entry_for(still, tmp_path, source)
    assert entry.camera is None and CAMERA_UNKNOWN in note
    entry = replace(entry, altitude=AltitudeSpec(constant_m=20.0, source="laser"),
                    animals=(Animal("dolphin 1", measurements=(ellipse_measurement(0),)),))
    project_path = tmp_path / "p.dolphinfit"
    write_project(project_path, Project(clips=(entry,)))
    return read_project(project_path), project_path


def test_a_still_without_a_camera_is_refused_until_one_is_set(tmp_path, camera):
    """No video preset is guessed: the results say why, and measure once a camera is set."""
    project, project_path = _unknown_camera_project(tmp_path)
    assert project.clips[0].camera is None   # kept unknown in the project file
    key = MeasurementKey(0, 0, 0)
    for measure in (lambda: measure_frame(project, key, 20.0, "laser", load_hw_preset(), 0),
                    lambda: measure_length(project, key, 20.0, "laser", 0)):
        with pytest.raises(InputError, match=f"still.png: {CAMERA_UNKNOWN}"):
            measure()
    results, skipped = frame_results(project, project_path, all_keys(project), 0)
    assert results == [] and skipped == [f"still.png frame 0: still.png: {CAMERA_UNKNOWN}"]
    project = Project(clips=(replace(project.clips[0], camera=camera),))
    assert measure_frame(project, key, 20.0, "laser", load_hw_preset(), 0).record["length_m"] > 0


def test_the_photos_camera_and_its_origin_survive_the_project_file(tmp_path):
    camera, _ = photo_camera(MINKE, *MINKE_SIZE)
    project, project_path = _unknown_camera_project(tmp_path)
    write_project(project_path, Project(clips=(replace(project.clips[0], camera=camera),)))
    reread = read_project(project_path).clips[0].camera
    assert reread.description == camera.description
    assert reread.intrinsics().focal_px == pytest.approx(camera.intrinsics().focal_px, rel=1e-12)
