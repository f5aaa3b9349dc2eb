"""The altitude calibration's line applied: to one altitude, a clip's telemetry, the intervals."""

from pathlib import Path

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.calibration_table import CalibrationShot, CalibrationTable
from dolphinfit.core.io.altitude_samples import AltitudeSource
from dolphinfit.core.io.telemetry import Telemetry
from dolphinfit.core.measure.altitude_calibration import (
    CalibrationCamera,
    calibrated_telemetry,
    fit_altitude_calibration,
    read_altitude_calibration,
    write_altitude_calibration,
)

CAMERA = CalibrationCamera(12.29, 17.27, 1920)


def _calibration(noise: float = 0.01, num: int = 40, seed: int = 0):
    """A fit to shots of a 2 m object from true = 0.5 m + 1.02 × recorded at 10–50 m."""
    rng = np.random.default_rng(seed)
    recorded = np.linspace(10.0, 50.0, num)
    pixels = 2.0 * CAMERA.focal_px / (0.5 + 1.02 * recorded) * (
        1 + noise * rng.standard_normal(num))
    shots = tuple(CalibrationShot(f"img{i}", float(h), float(p), 2.0, np.nan, np.nan, np.nan,
                                  "test drone") for i, (h, p) in enumerate(zip(recorded, pixels)))
    return fit_altitude_calibration(CalibrationTable(Path("shots.csv"), "altitude_m",
                                                     "test drone", shots), camera=CAMERA)


def test_exact_shots_give_the_line_and_no_spread():
    calibration = _calibration(noise=0.0)
    assert calibration.intercept_m == pytest.approx(0.5, abs=1e-9)
    assert calibration.slope == pytest.approx(1.02, abs=1e-12)
    assert calibration.residual_sd_fraction == pytest.approx(0.0, abs=1e-12)
    assert calibration.bias_only_m == pytest.approx(-(0.5 + 0.02 * 30.0), abs=1e-9)
    assert calibration.recorded_altitude(calibration.true_altitude(23.0)) == pytest.approx(23.0)


def test_the_prediction_sd_is_the_spread_plus_the_lines_own_error():
    """With 40 shots the line's own error adds little at the shots' mean altitude and more
    far from it; with 5 shots it adds more everywhere."""
    many, few = _calibration(num=40), _calibration(num=5, seed=1)
    spread = many.residual_sd_fraction
    assert spread < many.altitude_sd_fraction(30.0) < 1.05 * spread
    assert many.altitude_sd_fraction(30.0) < many.altitude_sd_fraction(80.0)
    assert few.altitude_sd_fraction(30.0) > 1.05 * few.residual_sd_fraction


def test_a_clips_altitudes_are_corrected_and_extrapolation_warned():
    calibration = _calibration()
    altitude = np.array([20.0, np.nan, 60.0])
    telemetry = Telemetry(altitude, np.arange(3) / 30.0, np.isnan(altitude),
                          np.zeros(3, bool), AltitudeSource("csv", Path("a.csv")))
    corrected = calibrated_telemetry(telemetry, calibration)
    np.testing.assert_allclose(corrected.altitude_m[[0, 2]],
                               calibration.true_altitude(altitude[[0, 2]]))
    assert np.isnan(corrected.altitude_m[1])
    (warning,) = corrected.warnings
    assert "60 m lies outside the calibrated 10–50 m" in warning


def test_another_cameras_focal_length_is_refused():
    calibration = _calibration()
    calibration.check_focal_px(CAMERA.focal_px * (1 + 1e-4), "clip.mp4")   # a preset's rounding
    with pytest.raises(InputError, match="clip.mp4: .* holds only for its own camera"):
        calibration.check_focal_px(CAMERA.focal_px * 1.5, "clip.mp4")


def test_written_calibration_reads_back_equal(tmp_path):
    calibration = _calibration()
    write_altitude_calibration(calibration, tmp_path / "cal.json")
    assert read_altitude_calibration(tmp_path / "cal.json") == calibration
    (tmp_path / "bad.json").write_text("{not json", encoding="utf-8")
    with pytest.raises(InputError, match="bad.json: not valid JSON"):
        read_altitude_calibration(tmp_path / "bad.json")
