"""The fit: end to end on a synthetic clip with known truth, and its controls."""

import json
import math
import re
import threading
from dataclasses import fields, replace
from pathlib import Path

import numpy as np
import pytest
import torch

from dolphinfit.app.cli import main
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit import losses
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.data import prepare_data
from dolphinfit.core.fit.engine import fit
from dolphinfit.core.fit.init import initial_state
from dolphinfit.core.fit.reporter import STAGE_ORDER
from dolphinfit.core.fit.result_io import (
    RESULT_JSON,
    RESULT_NPZ,
    read_fit_result,
    write_fit_result,
)
from dolphinfit.core.io.masks import read_png_folder
from dolphinfit.core.io.telemetry import load_telemetry
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.measure.altitude_calibration import write_altitude_calibration
from dolphinfit.core.progress import Cancelled

# conftest.py: the clip (a 2.3 m animal in 1920×1080 footage at 20 m, 8 frames, with the
# template's heights, which the fit then takes too), the configurations and the tiny fit.
from .conftest import INTRINSICS, QUICK, TINY, fit_on_clip


def _data(clip_dir, config=QUICK):
    clip = open_clip(clip_dir / "clip.mkv")
    masks = read_png_folder(clip_dir / "masks", clip)
    telemetry = load_telemetry(clip, clip_dir / "altitude.csv")
    with VideoReader(clip) as frames:
        return prepare_data(clip, frames.frame, masks, telemetry, INTRINSICS, config)


def _truth(clip_dir):
    return json.loads((clip_dir / "truth.json").read_text())


def test_end_to_end_volume_and_length_within_tolerance(clip_dir):
    """A synthetic clip's volume comes back within 5 % and its length within 3 %, with the
    animal at its depth (silhouettes alone would let depth and size trade)."""
    truth = _truth(clip_dir)
    result = fit(_data(clip_dir), QUICK)
    assert abs(result.volume_m3 / truth["volume_m3"] - 1) < 0.05
    assert abs(result.length_m / truth["length_m"] - 1) < 0.03
    true_z = np.array([f["transl_m"][2] for f in truth["frames"]])[result.frame_idx]
    assert np.abs(result.transl[:, 2] - true_z).max() < 0.05
    assert result.iou.mean() > 0.85
    assert result.posed_verts.shape == (len(result.frame_idx), 4002, 3)
    assert set(result.timings_s) >= {"heading", "global", "body", "shape", "total"}


def test_a_frame_cap_fits_fewer_frames_evenly_spaced(clip_dir):
    """``max_frames`` below the window's count: the fit takes every k-th of its frames, the
    smallest k that fits the cap, so its motion priors still see one interval."""
    every = _data(clip_dir).frame_idx
    capped = _data(clip_dir, replace(QUICK, max_frames=3)).frame_idx
    step = -(-len(every) // 3)
    np.testing.assert_array_equal(capped, every[::step])
    assert len(capped) <= 3 and len(set(np.diff(capped))) == 1


def test_a_fitted_frame_whose_altitude_is_impossible_is_left_out_and_named(clip_dir, tmp_path):
    """A 0-m row in the altitude CSV: the frame is left out of the fit with a warning naming
    it (not bridged from its neighbours); with every fitted frame's row 0 m (and others not)
    the fit refuses."""
    every = _data(clip_dir).frame_idx
    rows = (clip_dir / "altitude.csv").read_text().splitlines()
    zero = int(every[1])

    def written(zeroed: set[int]) -> Path:
        lines = [rows[0]] + [",".join([*row.split(",")[:-1], "0"]) if i in zeroed else row
                             for i, row in enumerate(rows[1:])]
        path = tmp_path / f"altitude_{len(zeroed)}.csv"
        path.write_text("\n".join(lines) + "\n")
        return path

    clip = open_clip(clip_dir / "clip.mkv")
    masks = read_png_folder(clip_dir / "masks", clip)
    with VideoReader(clip) as frames:
        data = prepare_data(clip, frames.frame, masks, load_telemetry(clip, written({zero})),
                            INTRINSICS, QUICK)
        assert zero not in data.frame_idx and len(data.frame_idx) == len(every) - 1
        assert any(f"left out: the altitude recorded there is impossible (frames {zero};" in w
                   and "outside the plausible 1–500 m" in w for w in data.warnings)
        few = replace(QUICK, max_frames=3)
        fitted = {int(t) for t in _data(clip_dir, few).frame_idx}
        with pytest.raises(InputError, match="the altitude recorded at every fitted frame is "
                                             "impossible"):
            prepare_data(clip, frames.frame, masks, load_telemetry(clip, written(fitted)),
                         INTRINSICS, few)


@pytest.mark.parametrize("width_px, cap_px, factor", [
    (28.0, 0, 1), (28.0, 15, 1), (28.0, 14, 2), (28.0, 7, 4), (28.0, 1, 16), (60.0, 20, 2)])
def test_the_fit_shrinks_by_a_power_of_two_that_keeps_the_animal_as_wide_as_asked(
        width_px, cap_px, factor):
    """The largest power of two that leaves the animal at least fit_width_px wide."""
    from dolphinfit.core.fit.data import fit_factor
    assert fit_factor(width_px, replace(QUICK, fit_width_px=cap_px)) == factor


def test_a_wide_animal_is_fitted_at_half_the_resolution_with_the_same_metric(clip_dir):
    """The clip's animal is about 28 px wide: asked to keep 13 px, the fit sees crops at half
    the resolution (each pixel the mean of 2 × 2), through a camera of half the focal length,
    the animal a quarter of the pixels, its edge's blur read before the binning; its volume
    and length come back within the full-resolution test's tolerances."""
    from dolphinfit.core.fit.data import edge_blur_of
    truth = _truth(clip_dir)
    native = _data(clip_dir)
    half = _data(clip_dir, replace(QUICK, fit_width_px=13))
    assert half.camera.intrinsics.focal_px == pytest.approx(native.camera.intrinsics.focal_px / 2)
    assert half.camera.intrinsics.width_px == 960
    assert abs(2 * half.viewport.width_px - native.viewport.width_px) <= 16
    assert np.abs(2 * half.viewport.x0_px.numpy() - native.viewport.x0_px.numpy()).max() <= 8
    assert float(4 * half.masks.sum() / native.masks.sum()) == pytest.approx(1.0, abs=0.03)
    # the edge's blur is read before the binning, which would have doubled it
    assert half.edge_blur_px == pytest.approx(native.edge_blur_px, rel=0.02)
    assert half.clip_px_per_px == 2.0 and native.clip_px_per_px == 1.0
    assert edge_blur_of(half) > 1.5 * native.edge_blur_px
    result = fit(half, QUICK)
    assert abs(result.volume_m3 / truth["volume_m3"] - 1) < 0.05
    assert abs(result.length_m / truth["length_m"] - 1) < 0.03


def test_initial_state_finds_position_heading_and_length(clip_dir):
    """From the masks alone: heading within 10° (mod 180°), centre within 15 cm, length 5 %."""
    truth = _truth(clip_dir)
    data = _data(clip_dir)
    state = initial_state(data, DolphinModel(), 0.15)
    true_heading = math.radians(-20.0)
    for heading in state.heading_rad:
        error = (heading - true_heading + math.pi / 2) % math.pi - math.pi / 2
        assert abs(math.degrees(error)) < 10
    true_xy = np.array([f["transl_m"][:2] for f in truth["frames"]])[data.frame_idx]
    assert np.linalg.norm(state.centre_xy - true_xy, axis=1).max() < 0.4
    assert abs(math.exp(state.log_scale) * 2.6 / truth["length_m"] - 1) < 0.05


def test_fit_is_deterministic_bit_for_bit_with_one_thread(clip_dir, tiny_run):
    """README's promise: with one torch thread (the tests' setting) the same data and
    configuration give the same result to the last bit."""
    assert torch.get_num_threads() == 1
    again = fit(_data(clip_dir, TINY), TINY)
    np.testing.assert_array_equal(tiny_run[0].result.betas, again.betas)
    np.testing.assert_array_equal(tiny_run[0].result.transl, again.transl)
    assert again.volume_m3 == tiny_run[0].result.volume_m3


def test_fit_with_more_threads_is_the_same_to_the_last_bit(clip_dir):
    """README's promise: chunks of frames run on as many workers as torch has threads, each
    on one thread, and gradients are summed in chunk order, so the thread count (2, and 3 for
    chunks that do not divide evenly) changes nothing; torch's count is restored after the
    fit."""
    config = replace(TINY, frames_per_chunk=3)
    one = fit(_data(clip_dir, TINY), config)
    for threads in (2, 3):
        torch.set_num_threads(threads)
        try:
            other = fit(_data(clip_dir, TINY), config)
            assert torch.get_num_threads() == threads
        finally:
            torch.set_num_threads(1)
        np.testing.assert_array_equal(one.betas, other.betas)
        np.testing.assert_array_equal(one.pose_aa, other.pose_aa)
        np.testing.assert_array_equal(one.iou, other.iou)
        assert one.volume_m3 == other.volume_m3


def test_config_has_no_seed_and_reads_configurations_that_carry_one():
    """Nothing in a fit is random, so it needs no seed: the field is gone, and results and
    configuration files written with it still read back."""
    assert "seed" not in FitConfig().to_json()
    assert FitConfig.from_json({**TINY.to_json(), "seed": 3}) == TINY


def test_progress_counts_every_step_in_stage_order(tiny_run):
    """Reports from "prepare" to "result": steps rise to the real total (both heading trials
    counted) and end there; the ETA appears with the first optimisation step."""
    run, reports = tiny_run
    total = 2 * 2 + 3 + 2 + 3
    assert run.result.status == "complete" and run.result.status_message == ""
    assert {r.total for r in reports} == {total}
    steps = [r.step for r in reports]
    assert steps == sorted(steps) and steps[-1] == total and max(steps) == total
    stages = list(dict.fromkeys(r.stage for r in reports))
    assert stages == list(STAGE_ORDER)
    prepare = [r for r in reports if r.stage == "prepare"]
    assert len(prepare) > len(run.data.frame_idx) and all(r.step == 0 for r in prepare)
    assert all(r.eta_s is None for r in reports if r.stage in ("prepare", "result"))
    optimising = [r for r in reports if r.stage not in ("prepare", "result")]
    assert all(r.eta_s is not None and r.eta_s >= 0 for r in optimising)
    assert optimising[-1].eta_s == 0 and "mean_iou" in optimising[-1].metrics
    assert [r.step for r in optimising if r.stage == "heading"][-1] == 4


@pytest.mark.parametrize("threads", [1, 2])
def test_cancel_keeps_the_best_state(clip_dir, threads):
    """Cancelled from the progress callback at step 3, the fit stops at once and returns its
    best state so far, saying so, also while worker threads render its chunks."""
    cancel = threading.Event()
    steps = []

    def on_progress(progress):
        steps.append(progress.step)
        if progress.step == 3:
            cancel.set()

    torch.set_num_threads(threads)
    try:
        result = fit(_data(clip_dir), replace(QUICK, frames_per_chunk=3), progress=on_progress,
                     cancel=cancel)
    finally:
        torch.set_num_threads(1)
    assert max(steps) == 3 and steps[-1] == 3
    assert result.status == "cancelled"
    assert result.status_message.startswith("cancelled by the user after 3 of 96 steps")
    assert "shape not fitted" in result.status_message
    assert np.isfinite(result.volume_m3) and result.iou.mean() > 0.3


def test_cancel_while_preparing_raises(clip_dir):
    """Cancelled before any optimisation step, there is nothing to keep."""
    cancel = threading.Event()

    def on_progress(progress):
        assert progress.stage == "prepare"
        cancel.set()

    with pytest.raises(Cancelled):
        fit_on_clip(clip_dir, TINY, progress=on_progress, cancel=cancel)


def test_diverging_fit_keeps_its_best_state(clip_dir, monkeypatch):
    """A non-finite loss ends the fit with finite, best-so-far values and status "diverged"."""
    real = losses.soft_iou_loss
    calls = {"n": 0}

    def poisoned(soft, target):
        calls["n"] += 1
        value = real(soft, target)
        return value * torch.nan if calls["n"] > 6 else value

    monkeypatch.setattr(losses, "soft_iou_loss", poisoned)
    result = fit(_data(clip_dir), QUICK)
    assert result.status == "diverged" and "non-finite" in result.status_message
    assert np.isfinite(result.volume_m3) and np.isfinite(result.transl).all()


def test_saved_fit_reads_back_field_for_field(tiny_run, tmp_path):
    """write_fit_result then read_fit_result gives every field back exactly."""
    result = tiny_run[0].result
    write_fit_result(result, tmp_path)
    again = read_fit_result(tmp_path)
    for field in fields(result):
        value, restored = getattr(result, field.name), getattr(again, field.name)
        if isinstance(value, np.ndarray):
            assert restored.dtype == value.dtype, field.name
            np.testing.assert_array_equal(restored, value, err_msg=field.name)
        elif field.name == "light":
            assert value.keys() == restored.keys()
            for key in value:
                np.testing.assert_array_equal(restored[key], value[key])
        else:
            assert restored == value, field.name


def test_a_fit_saved_before_new_fields_reads_back_as_it_was_made(tiny_run, tmp_path):
    """A result.json written before colour_geometry, profile_field, hw_table and the depth
    prior existed says what that fit did (the paper's colour term, no profile field, the
    template's heights, depth free), not today's defaults."""
    write_fit_result(tiny_run[0].result, tmp_path)
    json_path = tmp_path / RESULT_JSON
    data = json.loads(json_path.read_text())
    for name in ("colour_geometry", "profile_field", "hw_table"):
        del data["config"][name]
    del data["config"]["weights"]["depth"]
    json_path.write_text(json.dumps(data))
    config = read_fit_result(tmp_path).config
    assert (config.colour_geometry, config.profile_field, config.hw_table,
            config.weights.depth) == ("all_stages", False, None, 0.0)
    assert config.weights.pose == FitConfig().weights.pose
    assert FitConfig().profile_field and FitConfig().hw_table == "tursiops-provisional"
    assert FitConfig().weights.depth > 0


def test_broken_saved_fits_name_the_file(tiny_run, tmp_path):
    """A missing or truncated npz and a foreign schema version are input errors naming the
    file."""
    write_fit_result(tiny_run[0].result, tmp_path)
    npz, json_path = tmp_path / RESULT_NPZ, tmp_path / RESULT_JSON
    npz.write_bytes(npz.read_bytes()[: npz.stat().st_size // 2])
    with pytest.raises(InputError, match=re.escape(str(npz))):
        read_fit_result(tmp_path)
    npz.unlink()
    with pytest.raises(InputError, match=re.escape(f"{npz}: the fit's arrays are missing")):
        read_fit_result(tmp_path)
    data = json.loads(json_path.read_text())
    json_path.write_text(json.dumps({**data, "schema_version": 1}))
    with pytest.raises(InputError, match=re.escape(f"{json_path}: schema_version 1")):
        read_fit_result(tmp_path)


def test_config_round_trips_and_rejects_nonsense():
    """FitConfig survives JSON; bad values are input errors."""
    from dolphinfit.core.errors import InputError
    assert FitConfig.from_json(json.loads(json.dumps(QUICK.to_json()))) == QUICK
    with pytest.raises(InputError, match="fps"):
        replace(QUICK, fps=0.0)
    with pytest.raises(InputError, match="unknown"):
        FitConfig.from_json({"steps": 3})


def test_cli_fit_writes_result_meshes_and_overlays(clip_dir, tmp_path, capsys):
    """`dolphinfit fit` writes result.json, the rest mesh, posed meshes and overlays and prints
    the figures with their 95 % intervals (an altitude CSV: the manual altitude error unless
    --altitude-source says otherwise); --hw picks the table of the hidden heights ("model":
    the template's own)."""
    config = tmp_path / "quick.json"
    config.write_text(json.dumps(TINY.to_json()))
    out = tmp_path / "out"
    argv = ["fit", str(clip_dir / "clip.mkv"), "--altitude", str(clip_dir / "altitude.csv"),
            "--masks", str(clip_dir / "masks"), "--sensor-width-mm", "17.27", "--focal-mm",
            "12.29", "--config", str(config), "--out", str(out), "--hw", "circular",
            "--altitude-source", "laser"]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    result = json.loads((out / "result.json").read_text())
    shown = re.search(r"volume (\S+) \((\S+)–(\S+)\) m³", printed)
    value, low, high = map(float, shown.groups())
    assert low < value < high and value == pytest.approx(result["volume_m3"], abs=1e-4)
    assert "altitude from the laser" in printed
    saved = json.loads((out / "interval.json").read_text())
    assert saved["altitude_source"] == "laser" and saved["errors"]["altitude_sd_fraction"] == 0.01
    assert saved["volume_m3"]["low"] == pytest.approx(low, abs=1e-4)
    assert saved["volume_m3"]["high"] == pytest.approx(high, abs=1e-4)
    for key in ("volume_m3", "length_m", "mass_kg", "bci", "frames", "timings"):
        assert key in result
    assert result["config"]["hw_table"] == "circular"
    assert np.asarray(result["profile"]).shape == (2, 10)
    assert len(list((out / "posed").glob("*.ply"))) == len(result["frames"])
    assert (out / "rest_mesh.ply").exists() and list((out / "overlays").glob("*.png"))
    assert result["status"] == "complete"
    assert len(read_fit_result(out).posed_verts) == len(result["frames"])
    assert main(["fit", str(clip_dir / "clip.mkv"), "--altitude", "high"]) == 2
    assert "neither a number" in capsys.readouterr().err


def test_without_masks_the_tracker_finds_the_dolphin(clip_dir):
    """run_fit with no mask files finds the dolphin itself (a scan of the fit's window picks
    it, the network back-end tracks it on the frames the fit looks at only) and fits it."""
    from dolphinfit.core.fit.pipeline import CameraChoice, run_fit
    from dolphinfit.core.segment.net_tracker import BACKEND_NAME

    run = run_fit(clip_dir / "clip.mkv", clip_dir / "altitude.csv", None,
                  CameraChoice(sensor_width_mm=17.27, focal_mm=12.29), TINY)
    assert run.masks.source.startswith(BACKEND_NAME)
    assert "1 animal kept; took dolphin 1" in run.masks.source
    assert run.masks.is_visible.sum() >= 6
    assert set(run.result.frame_idx) <= set(np.flatnonzero(run.masks.is_visible))
    assert run.result.iou.mean() > 0.6


def test_the_automatic_seed_looks_for_a_dolphins_length_at_the_clips_altitudes():
    """1–4 m at 15–25 m with a 1000 px focal length: 40–267 px; no altitude: any length."""
    from dolphinfit.core.segment.auto_seed import DOLPHIN_LENGTH_M, expected_length_px

    low, high = expected_length_px(1000.0, np.array([15.0, np.nan, 25.0]), DOLPHIN_LENGTH_M)
    assert (low, high) == pytest.approx((40.0, 4000.0 / 15.0))
    assert expected_length_px(1000.0, np.array([np.nan]), DOLPHIN_LENGTH_M) is None


def test_a_fit_that_cannot_be_trusted_says_why():
    """Each reason alone: too few frames, a mean IoU under 0.7 (masks of a seagrass patch gave
    0.61 on the bench suite), masks 2.9 times as long as wide (half an animal), an animal 12
    px wide; a good fit of a whole animal has none."""
    from dolphinfit.core.fit.reliability import unreliable_reasons

    good = np.array([0.9, 0.85, 0.75, 0.8, 0.9])
    assert unreliable_reasons(5, good, 5.2, 30.0) == ()
    (frames,) = unreliable_reasons(3, good[:3], 5.2, 30.0)
    assert "only 3 frame(s)" in frames
    (poor,) = unreliable_reasons(5, np.array([0.7, 0.6, 0.55, 0.6, 0.65]), 5.2, 30.0)
    assert "poor fit" in poor and "0.62" in poor
    (part,) = unreliable_reasons(5, good, 2.9, 30.0)
    assert "partial body" in part and "2.9 times" in part
    (narrow,) = unreliable_reasons(5, good, 5.2, 12.0)
    assert "only 12 px wide" in narrow and "about 3 %" in narrow
    assert len(unreliable_reasons(2, np.array([0.5, 0.6]), 2.0, 8.0)) == 4


def _ellipses(width_px: int, lengths_px: tuple[int, ...]) -> np.ndarray:
    import cv2

    mask = np.zeros((len(lengths_px), 120, 240), np.uint8)
    for frame, length in zip(mask, lengths_px):
        cv2.ellipse(frame, (120, 60), (length // 2, width_px // 2), 15, 0, 360, 1, -1)
    return mask.astype(bool)


def test_masks_shorter_than_the_animal_are_partial_and_a_whole_one_is_elongated():
    """Of six frames of a 180-px body, the two 130 px long (the front of it) are partial;
    widest_px reads a disc's diameter; an ellipse 180 × 36 is five times as long as wide."""
    import cv2

    from dolphinfit.core.fit.whole_body import elongation, length_px, partial, widest_px

    masks = _ellipses(36, (180, 178, 130, 181, 130, 179))
    lengths = np.array([length_px(mask) for mask in masks])
    assert lengths[0] == pytest.approx(181, abs=2)
    assert partial(lengths * 0.01).tolist() == [False, False, True, False, True, False]
    disc = np.zeros((100, 100), np.uint8)
    cv2.circle(disc, (50, 50), 20, 1, -1)
    assert widest_px(disc.astype(bool)) == pytest.approx(41.0, abs=1.5)
    assert elongation(masks[0]) == pytest.approx(5.0, abs=0.2)


def test_cli_fit_with_an_altitude_calibration(clip_dir, tiny_run, tmp_path, capsys):
    """A calibration of the clip's camera: its spread is the intervals' altitude error (the
    camera's own error then left out, the line absorbed it); one of another camera is refused
    before any work."""
    from dolphinfit.app.commands.fit import fit_error_model
    from dolphinfit.core.fit.pipeline import CameraChoice
    from tests.core.measure.test_altitude_calibration import _calibration

    run, _ = tiny_run
    calibration = _calibration()
    errors = fit_error_model(run, "barometer", CameraChoice(None, 17.27, 12.29), calibration)
    recorded = calibration.recorded_altitude(float(run.data.camera.altitude_m.median()))
    assert errors.altitude_sd_fraction == calibration.altitude_sd_fraction(recorded)
    assert errors.altitude_sd_fraction < 0.02 and errors.focal_sd_fraction == 0.0
    other = tmp_path / "other.json"
    write_altitude_calibration(replace(calibration, camera=replace(
        calibration.camera, focal_mm=24.0)), other)
    assert main(["fit", str(clip_dir / "clip.mkv"), "--altitude", str(clip_dir / "altitude.csv"),
                 "--masks", str(clip_dir / "masks"), "--sensor-width-mm", "17.27",
                 "--focal-mm", "12.29", "--out", str(tmp_path / "out"),
                 "--altitude-calibration", str(other)]) == 2
    assert "holds only for its own camera" in capsys.readouterr().err
    assert not (tmp_path / "out" / "result.json").exists()


def test_the_fit_measures_its_edges_blur_and_its_interval_takes_the_larger_rule(tiny_run):
    """The synthetic clip's edge reads a blur index of about 1 px; the outline SD of the fit's
    interval is the larger of the frame-width rule (0.36 px at 1920) and 0.35 × the index."""
    from dolphinfit.core.fit.interval import run_interval
    from dolphinfit.core.measure.fit_uncertainty import OUTLINE_SD_OF_WIDTH, OUTLINE_SD_PER_BLUR
    from dolphinfit.core.measure.uncertainty import ErrorModel

    run, _ = tiny_run
    blur = run.result.edge_blur_px
    assert 0.5 < blur < 2.0
    interval = run_interval(run, ErrorModel.default("laser", False))
    assert interval.outline_sd_px == pytest.approx(max(OUTLINE_SD_OF_WIDTH * 1920,
                                                       OUTLINE_SD_PER_BLUR * blur))


def _full_frame_masks(data) -> np.ndarray:
    """The fit's mask crops put back in their (H, W) frames."""
    full = np.zeros((data.num_frames, INTRINSICS.height_px, INTRINSICS.width_px), bool)
    height, width = data.masks.shape[1:]
    for t, (x0, y0) in enumerate(zip(data.viewport.x0_px.tolist(), data.viewport.y0_px.tolist())):
        full[t, y0:y0 + height, x0:x0 + width] = data.masks[t].numpy() > 0.5
    return full


def _iou(a: np.ndarray, b: np.ndarray) -> float:
    return float((a & b).sum() / (a | b).sum())


def test_a_lens_model_undistorts_what_the_fit_sees(clip_dir):
    """The clip seen through a barrel lens (k1 −0.25, its centre 700 px from the animal:
    the masks move tens of pixels) and prepared through the lens's model reaches the fit as
    the pinhole camera showed it: mask IoU 0.987 with the undistorted clip's, 0.07 as
    seen."""
    import cv2

    from dolphinfit.core.measure.lens import LensModel

    clip = open_clip(clip_dir / "clip.mkv")
    masks = read_png_folder(clip_dir / "masks", clip)
    telemetry = load_telemetry(clip, clip_dir / "altitude.csv")
    rows, cols = np.nonzero(masks.load(int(np.flatnonzero(masks.is_visible)[0])))
    centre = np.array([cols.mean(), rows.mean()]) - [560.0, 420.0]
    focal = INTRINSICS.focal_px
    lens = LensModel(1920, 1080, focal, focal, *centre, (-0.25, 0.0, 0.0, 0.0, 0.0), 0.0, 9,
                     "test lens")
    v, u = np.mgrid[0:1080, 0:1920]
    pixels = np.stack([u, v], -1).reshape(-1, 1, 2).astype(np.float64)
    to_ideal = cv2.undistortPoints(pixels, lens.matrix(), np.array(lens.distortion),
                                   P=lens.matrix()).reshape(1080, 1920, 2).astype(np.float32)

    def seen(image: np.ndarray) -> np.ndarray:
        return cv2.remap(image, to_ideal[..., 0], to_ideal[..., 1], cv2.INTER_LINEAR)

    seen_masks = replace(masks, load=lambda f: seen(masks.load(f).astype(np.uint8) * 255) >= 128)
    with VideoReader(clip) as frames:
        fixed = prepare_data(clip, lambda i: seen(frames.frame(i)), seen_masks, telemetry,
                             INTRINSICS, QUICK, lens=lens)
    truth = np.stack([masks.mask(int(f)) for f in fixed.frame_idx])
    as_seen = np.stack([seen_masks.mask(int(f)) for f in fixed.frame_idx])
    assert _iou(as_seen, truth) < 0.2
    assert _iou(_full_frame_masks(fixed), truth) > 0.97
    assert not any("lens" in w for w in fixed.warnings)


def test_through_a_barrel_lens_an_animal_at_the_edge_is_left_out():
    """Undistorting pushes what lies near the frame's edge outwards: a mask 20 px from the
    right edge ends against it and its frame is skipped, naming it; one at the centre stays;
    with none left, an InputError names the clip."""
    import cv2

    from dolphinfit.core.fit.data import _masks_through_lens
    from dolphinfit.core.measure.lens import LensModel

    lens = LensModel(1280, 720, 900.0, 900.0, 639.5, 359.5, (-0.12, 0.05, 0.0, 0.0, 0.0), 0.1,
                     9, "test")
    masks = np.zeros((2, 720, 1280), np.uint8)
    cv2.ellipse(masks[0], (640, 360), (120, 25), 0, 0, 360, 1, -1)
    cv2.ellipse(masks[1], (1140, 360), (120, 25), 0, 0, 360, 1, -1)   # 20 px from the edge

    class Clip:
        path = Path("edge.mp4")

    idx, kept, warnings = _masks_through_lens(Clip, np.array([3, 7]), masks.astype(bool), lens)
    assert idx.tolist() == [3] and kept.shape == (1, 720, 1280)
    assert warnings == ["1 frame(s) skipped: through the lens model the dolphin reaches the "
                        "frame's edge (frames 7)"]
    with pytest.raises(InputError, match="edge.mp4: through the lens model, the dolphin "
                                         "reaches the frame's edge in every chosen frame"):
        _masks_through_lens(Clip, np.array([7]), masks[1:].astype(bool), lens)


def test_a_fit_of_half_an_animal_is_unreliable_and_says_so(clip_dir, tmp_path, capsys):
    """Masks that hold only the front half of the animal in every frame: the fit runs to its
    end, but its status is "unreliable" with the partial body as its reason, in result.json
    and on the command's last line (exit 0: the figures are written, marked)."""
    import cv2

    halves = tmp_path / "halves"
    halves.mkdir()
    for path in sorted((clip_dir / "masks").glob("*.png")):
        mask = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
        rows, cols = np.nonzero(mask)
        # the animal heads right and a little up (heading -20°): keep its right half
        mask[:, :int(np.median(cols))] = 0
        cv2.imwrite(str(halves / path.name), mask)
    config = tmp_path / "quick.json"
    config.write_text(json.dumps(QUICK.to_json()))
    out = tmp_path / "out"
    assert main(["fit", str(clip_dir / "clip.mkv"), "--altitude", str(clip_dir / "altitude.csv"),
                 "--masks", str(halves), "--sensor-width-mm", "17.27", "--focal-mm", "12.29",
                 "--config", str(config), "--out", str(out)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith("status: unreliable: a partial body")
    result = json.loads((out / "result.json").read_text())
    assert result["status"] == "unreliable"
    assert any("partial body" in reason for reason in result["reasons"])
    assert read_fit_result(out).reasons == tuple(result["reasons"])
