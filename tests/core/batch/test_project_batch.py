"""A project's animals as batch tasks: the fit as the app sets it, the elliptical baseline on
the frames measured in the app."""

import cv2
import numpy as np
import pytest

from dolphinfit.core.batch.cluster import batch_client, local_plan
from dolphinfit.core.batch.project_tasks import project_tasks
from dolphinfit.core.batch.runner import run_batch
from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.measure.stations import NUM_STATIONS
from dolphinfit.core.project.fit_settings import FitSettings, fit_dir
from dolphinfit.core.project.model import AltitudeSpec, Animal, ClipEntry, Measurement, Project
from dolphinfit.core.project.project_file import write_project

CAMERA = CameraPreset(name="test", description="test camera", focal_mm=12.29,
                      sensor_width_mm=17.27, image_width_px=320, image_height_px=180,
                      source="test", approximate=False)
ALTITUDE_M = 10.0
# A straight midline of 100 px with every width 20 px (±10 px)
MEASUREMENT = Measurement(frame_idx=0, midline_px=np.array([[100.0, 90.0], [200.0, 90.0]]),
                          offsets_px=np.tile([10.0, -10.0], (NUM_STATIONS, 1)))


@pytest.fixture
def project_path(tmp_path):
    cv2.imwrite(str(tmp_path / "still.png"), np.zeros((180, 320, 3), np.uint8))
    (tmp_path / "DJI_0001.MP4").write_bytes(b"not decoded here")
    still = ClipEntry(media_path="still.png", kind="image", camera=CAMERA,
                      altitude=AltitudeSpec(constant_m=ALTITUDE_M, source="laser"),
                      animals=(Animal("A", measurements=(MEASUREMENT,)), Animal("B")))
    video = ClipEntry(media_path="DJI_0001.MP4", kind="video", camera=CAMERA,
                      altitude=AltitudeSpec(path="DJI_0001.SRT", launch_height_m=1.5,
                                            source="barometer"),
                      masks_path="masks",
                      animals=(Animal("C", fit_settings=FitSettings(fps=2.0, quality="quick",
                                                                    start_s=1.0)),))
    path = tmp_path / "survey.dolphinfit"
    write_project(path, Project(clips=(still, video)))
    return path


def test_every_animal_is_a_task_fitted_as_the_app_would(project_path):
    a, b, c = project_tasks(project_path, num_draws=50)
    assert [t.animal_id for t in (a, b, c)] == ["A", "B", "C"]
    assert a.fit is None and b.fit is None  # a still is measured, not fitted
    assert c.name == fit_dir(project_path, "DJI_0001.MP4", "C").name
    assert c.fit.altitude == project_path.parent / "DJI_0001.SRT"
    assert c.fit.launch_height_m == 1.5
    assert c.fit.masks == project_path.parent / "masks"
    assert (c.fit.camera.sensor_width_mm, c.fit.camera.focal_mm) == (17.27, 12.29)
    assert (c.fit.config.fps, c.fit.config.start_s, c.fit.config.steps_body) == (2.0, 1.0, 20)


def test_project_batch_measures_the_measured_frames(project_path, tmp_path):
    tasks = project_tasks(project_path, num_draws=200)[:2]
    with batch_client(plan=local_plan(1, 1), processes=False) as client:
        measured, unmeasured = run_batch(client, tasks, tmp_path / "out")
    assert measured.status == "complete" and unmeasured.status == "complete"
    m_per_px = ALTITUDE_M / (12.29 / 17.27 * 320)
    assert measured.values["length_m_ell"] == pytest.approx(100 * m_per_px, rel=1e-9)
    assert measured.values["Image_ID"] == "still"
    assert (measured.values["volume_m3_ell_lo95"] < measured.values["volume_m3_ell"]
            < measured.values["volume_m3_ell_hi95"])
    assert "length_m_fit" not in measured.values
    assert "no frame measured" in unmeasured.values["notes"]
    assert (tmp_path / "out" / measured.name / "elliptical_still_measure.json").is_file()
