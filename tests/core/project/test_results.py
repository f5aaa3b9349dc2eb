"""Per-frame results are the CLI's chain on the same pixels; per-animal spread over frames."""

import cv2
import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.telemetry import constant_telemetry
from dolphinfit.core.io.video import Clip
from dolphinfit.core.measure.annotation import pixel_measurements
from dolphinfit.core.measure.baseline import BaselineSettings, estimate_baseline
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.mask_midline import midline_from_mask
from dolphinfit.core.measure.uncertainty import ErrorModel
from dolphinfit.core.project.evaluate import all_keys, frame_results
from dolphinfit.core.project.model import Measurement, MeasurementKey, with_clip, with_measurement
from dolphinfit.core.project.project_file import write_project
from dolphinfit.core.measure.elliptical import NoWidthError
from dolphinfit.core.project.results import (
    animal_summary, frame_altitude, image_id, measure_frame, measure_length, spread,
)

from .conftest import write_black_clip


def test_frame_result_equals_the_engine_on_the_same_pixels(project):
    hw = load_hw_preset()
    key = MeasurementKey(0, 0, 0)
    result = measure_frame(project, key, 18.0, "laser", hw, num_draws=0)
    clip = project.clips[0]
    pixels = pixel_measurements(clip.animals[0].measurements[0].to_annotation())
    focal_px = clip.camera.intrinsics().focal_px
    direct = estimate_baseline(pixels, focal_px, 18.0, BaselineSettings(hw=hw),
                               ErrorModel.default("laser", False), 0,
                               np.random.default_rng(0))
    assert result.record["volume_m3"] == pytest.approx(float(direct.point.volume_m3), rel=1e-12)
    assert result.record["length_m"] == pytest.approx(600 * 18.0 / focal_px, rel=1e-9)
    assert result.image_id == "clip_f000003"


def test_a_frame_with_a_length_and_no_width_gets_its_length_and_interval(project):
    """The length alone equals the full estimate's on the same midline, and its Monte Carlo
    (laser altitude SD 1 %, verified camera 0.5 %, two end points at the digitisation SD)
    centres on it with a 95 % interval about ±2 × 1.1 % wide; the full estimate refuses the
    frame with NoWidthError."""
    key = MeasurementKey(0, 0, 0)
    full = measure_frame(project, key, 18.0, "laser", load_hw_preset(), num_draws=0)
    measured = project.clips[0].animals[0].measurements[0]
    bare = with_measurement(project, key, Measurement(3, midline_px=measured.midline_px))
    with pytest.raises(NoWidthError):
        measure_frame(bare, key, 18.0, "laser", load_hw_preset(), num_draws=0)
    nominal = measure_length(bare, key, 18.0, "laser", num_draws=0)
    assert nominal.interval is None and nominal.image_id == full.image_id
    assert nominal.length_m == pytest.approx(full.record["length_m"], rel=1e-12)
    assert nominal.m_per_px == pytest.approx(full.estimate.m_per_px, rel=1e-12)
    drawn = measure_length(bare, key, 18.0, "laser", num_draws=20_000).interval
    errors = ErrorModel.default("laser", False)
    share = np.hypot(errors.altitude_sd_fraction, errors.focal_sd_fraction)
    assert float(drawn.mean) == pytest.approx(nominal.length_m, rel=2e-3)
    assert float(drawn.sd) / nominal.length_m == pytest.approx(share, rel=0.1)
    assert float(drawn.low) < nominal.length_m < float(drawn.high)
    with pytest.raises(ValueError, match="no body length"):
        measure_length(with_measurement(project, key, Measurement(3)), key, 18.0, "laser", 0)


def test_animal_summary_is_mean_sd_and_range_over_frames(project):
    hw = load_hw_preset()
    results = [measure_frame(project, MeasurementKey(0, 0, m), 18.0, "laser", hw, 0)
               for m in range(2)]
    summary = animal_summary(results)
    volumes = [r.record["volume_m3"] for r in results]
    assert summary["volume_m3"].mean == pytest.approx(np.mean(volumes))
    assert summary["volume_m3"].sd == pytest.approx(np.std(volumes, ddof=1))
    assert (summary["volume_m3"].low, summary["volume_m3"].high) == (min(volumes), max(volumes))
    assert np.isnan(spread([1.0]).sd)
    with pytest.raises(ValueError):
        spread([])


def test_frames_without_length_or_altitude_say_why(project):
    empty = with_measurement(project, MeasurementKey(0, 0, 0), Measurement(frame_idx=3))
    with pytest.raises(ValueError, match="no body length"):
        measure_frame(empty, MeasurementKey(0, 0, 0), 18.0, "laser", load_hw_preset(), 0)
    clip = Clip(path=None, fps=10.0, num_frames=5, width_px=1280, height_px=720)
    telemetry = constant_telemetry(18.0, clip)
    assert frame_altitude(telemetry, 4) == 18.0
    with pytest.raises(InputError, match="outside"):
        frame_altitude(telemetry, 5)
    with pytest.raises(InputError, match="Altitude"):
        frame_altitude(None, 0)
    assert image_id(project.clips[0], 12) == "clip_f000012"


def test_project_results_open_each_clip_and_report_unmeasurable_frames(tmp_path, project):
    write_black_clip(tmp_path / "media")
    path = tmp_path / "p.dolphinfit"
    write_project(path, project)
    done = []
    results, skipped = frame_results(project, path, all_keys(project), num_draws=50,
                                     progress=lambda p: done.append((p.step, p.total)))
    assert [r.image_id for r in results] == ["clip_f000003", "clip_f000007"]
    assert results[0].estimate.interval is not None and skipped == []
    assert done[-1] == (2, 2)
    assert all_keys(project, clip=0, animal=1) == []


def test_midline_from_mask_runs_rostrum_to_flukes():
    mask = np.zeros((300, 600), np.uint8)
    cv2.ellipse(mask, (300, 150), (220, 35), 0, 0, 360, 1, -1)
    cv2.rectangle(mask, (505, 100), (525, 200), 1, -1)  # flukes at the right end
    midline = midline_from_mask(mask.astype(bool))
    assert midline[0][0] < 100 and midline[-1][0] > 500
    np.testing.assert_allclose(midline[1:-1, 1], 150.0, atol=1.0)
    flipped = midline_from_mask(mask[:, ::-1].astype(bool))
    assert flipped[0][0] > 500
    with pytest.raises(ValueError):
        midline_from_mask(np.zeros((10, 10), bool))


def test_the_fit_takes_its_hidden_heights_from_the_projects_hw_table(project, tmp_path):
    """Both methods take the heights a top view cannot see from the project's table: a
    preset by name, a project CSV made absolute, and "model" (the elliptical baseline's
    ratios from the template) as the template's own heights (hw_table None)."""
    from dataclasses import replace

    from dolphinfit.core.project.fit_settings import FitSettings
    from dolphinfit.core.project.results import project_fit_config

    settings = FitSettings(fps=2.0)
    for spec, expected in (("circular", "circular"), ("model", None),
                           ("tables/hw.csv", str(tmp_path / "tables/hw.csv"))):
        config = project_fit_config(settings, replace(project, hw_ratios=spec), tmp_path)
        assert config.hw_table == expected and config.fps == 2.0


def test_a_clips_lens_model_straightens_the_clicks_before_measuring(project):
    """With the clip's lens model the frame measures as its clicks taken through it (the
    CLI's --lens); a lens of another video mode is refused naming it; without a lens, a frame
    measured near the corner is warned about."""
    from dataclasses import replace

    from dolphinfit.core.measure.lens import LensModel, undistorted_annotation

    lens = LensModel(1280, 720, 900.0, 900.0, 639.5, 359.5, (-0.12, 0.05, 0.0, 0.0, 0.0),
                     0.05, 9, "test")
    key = MeasurementKey(0, 0, 0)
    clip = project.clips[0]
    through = with_clip(project, 0, replace(clip, lens=lens))
    result = measure_frame(through, key, 18.0, "laser", load_hw_preset(), num_draws=0)
    straight = undistorted_annotation(clip.animals[0].measurements[0].to_annotation(), lens)
    focal_px = clip.camera.intrinsics().focal_px
    assert result.record["length_m"] == pytest.approx(
        pixel_measurements(straight).length_px * 18.0 / focal_px, rel=1e-9)
    plain = measure_frame(project, key, 18.0, "laser", load_hw_preset(), num_draws=0)
    assert result.record["length_m"] > plain.record["length_m"]  # barrel: clicks read short
    assert not any("lens" in w for w in plain.record["warnings"])  # near the centre
    other = with_clip(project, 0, replace(clip, lens=replace(lens, width_px=1920)))
    with pytest.raises(InputError, match="lens model of clip.mp4: the lens was calibrated on "
                                         "1920×720"):
        measure_frame(other, key, 18.0, "laser", load_hw_preset(), num_draws=0)
    measurement = clip.animals[0].measurements[0]
    cornered = with_measurement(project, key, replace(
        measurement, midline_px=measurement.midline_px + [550.0, 300.0]))
    far = measure_frame(cornered, key, 18.0, "laser", load_hw_preset(), num_draws=0)
    assert any("without a lens model" in w for w in far.record["warnings"])
