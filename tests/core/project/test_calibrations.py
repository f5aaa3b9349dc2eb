"""A project's altitude calibrations: kept in the project file, fitted from their shots, and
applied to the results of the clips that name them."""

from dataclasses import replace

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.project.calibrations import clip_calibration, fitted_calibration
from dolphinfit.core.project.model import (
    AltitudeCalibrationSet, MeasurementKey, ObjectShot, Project,
)
from dolphinfit.core.project.project_file import project_from_json, project_to_json
from dolphinfit.core.project.results import measure_frame, measure_length

KEY = MeasurementKey(0, 0, 0)


def calibration_set(camera, name: str = "test drone barometer", noise: float = 0.01,
                    num: int = 12) -> AltitudeCalibrationSet:
    """Shots of a 2 m board from true = 0.5 m + 1.05 × recorded at 10–40 m."""
    rng = np.random.default_rng(5)
    focal_px = camera.intrinsics().focal_px
    recorded = np.linspace(10.0, 40.0, num)
    pixels = 2.0 * focal_px / (0.5 + 1.05 * recorded) * (1 + noise * rng.standard_normal(num))
    shots = tuple(ObjectShot(f"board_{i}.jpg", float(h), float(p),
                             ((100.0, 200.0), (100.0 + float(p), 200.0)))
                  for i, (h, p) in enumerate(zip(recorded, pixels)))
    return AltitudeCalibrationSet(name, 2.0, camera, "barometer", shots)


def _calibrated(project: Project, camera) -> Project:
    return replace(project, calibrations=(calibration_set(camera),),
                   clips=(replace(project.clips[0],
                                  altitude_calibration="test drone barometer"),))


def test_calibrations_survive_the_project_file(project, camera):
    calibrated = _calibrated(project, camera)
    again = project_from_json(project_to_json(calibrated), "p.dolphinfit")
    (read,), (written,) = again.calibrations, calibrated.calibrations
    assert replace(read, camera=camera) == written   # its camera comes back by its values
    assert read.camera.intrinsics() == camera.intrinsics()
    assert again.clips[0].altitude_calibration == "test drone barometer"
    older = project_to_json(project)
    del older["calibrations"], older["clips"][0]["altitude_calibration"]
    assert project_from_json(older, "old.dolphinfit").calibrations == ()  # files before them


def test_a_clip_naming_an_unknown_calibration_is_refused(project, camera):
    data = project_to_json(_calibrated(project, camera))
    data["calibrations"] = []
    with pytest.raises(InputError, match="names an altitude calibration the project lacks"):
        project_from_json(data, "p.dolphinfit")
    data = project_to_json(_calibrated(project, camera))
    data["calibrations"][0]["shots"][0]["ends_px"] = [[1, 2]]
    with pytest.raises(InputError, match=r"shots\[0\]: ends_px must be the object's two ends"):
        project_from_json(data, "p.dolphinfit")


def test_results_of_a_calibrated_clip_use_the_line_and_its_spread(project, camera):
    """The frame at a recorded 18 m is measured at the line's 19.4 m: its length grows by that
    ratio, and a barometer's ±5 % interval narrows to the calibration's ~1 %."""
    hw = load_hw_preset()
    plain = measure_frame(project, KEY, 18.0, "barometer", hw, num_draws=2000)
    calibrated_project = _calibrated(project, camera)
    calibration = clip_calibration(calibrated_project, 0)
    calibrated = measure_frame(calibrated_project, KEY, 18.0, "barometer", hw, num_draws=2000)
    altitude = calibration.true_altitude(18.0)
    assert altitude == pytest.approx(0.5 + 1.05 * 18.0, abs=0.2)
    assert calibrated.record["altitude_m"] == pytest.approx(altitude)
    assert calibrated.record["recorded_altitude_m"] == 18.0
    assert calibrated.record["length_m"] == pytest.approx(
        plain.record["length_m"] * altitude / 18.0, rel=1e-9)

    def width(result):
        interval = result.record["uncertainty"]["volume_m3"]
        return (interval["high"] - interval["low"]) / result.record["volume_m3"]

    assert width(plain) > 2.5 * width(calibrated)
    length = measure_length(calibrated_project, KEY, 18.0, "barometer", num_draws=0)
    assert length.altitude_m == pytest.approx(altitude)
    assert length.length_m == pytest.approx(calibrated.record["length_m"], rel=1e-9)


def test_a_calibration_too_thin_to_fit_says_why(project, camera):
    thin = calibration_set(camera, num=3)
    with pytest.raises(InputError, match="test drone barometer: 3 usable shots"):
        fitted_calibration(thin)
    assert fitted_calibration(calibration_set(camera)) is fitted_calibration(
        calibration_set(camera))   # fitted once per set


def test_a_renamed_calibration_moves_its_clips_and_frees_the_unticked(project, camera):
    from dolphinfit.core.project.model import add_clip, with_calibration

    two = add_clip(project, replace(project.clips[0], media_path="media/other.mp4"))
    first = with_calibration(two, calibration_set(camera, "old"), (0, 1))
    assert [c.altitude_calibration for c in first.clips] == ["old", "old"]
    renamed = with_calibration(first, calibration_set(camera, "new"), (1,), replacing="old")
    assert [c.name for c in renamed.calibrations] == ["new"]
    assert [c.altitude_calibration for c in renamed.clips] == [None, "new"]
