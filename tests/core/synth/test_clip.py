"""Synthetic clips: files, truth, determinism, masks against the geometry, telemetry."""

import json
import threading
from dataclasses import replace

import cv2
import numpy as np
import pytest
import torch

from dolphinfit.app.cli import main
from dolphinfit.core.camera import NadirCamera
from dolphinfit.core.errors import InputError
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.io.telemetry import load_telemetry
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.measure.condition import body_condition
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.template import load_template
from dolphinfit.core.progress import Cancelled
from dolphinfit.core.render.rasterize import rasterize
from dolphinfit.core.render.render import project_to_viewport
from dolphinfit.core.render.settings import Viewport
from dolphinfit.core.segment.evaluate import outline_offset_px
from dolphinfit.core.synth import sample
from dolphinfit.core.synth.clip import make_clip
from dolphinfit.core.synth.config import Effects, SynthConfig

SMALL = SynthConfig(seed=3, width_px=320, height_px=240, fps=5.0, duration_s=1.2,
                    altitude_m=6.0, length_m=2.3, heading_deg=30.0, speed_m_s=1.0)
PLAIN = Effects(profile_warp=False, finer_mesh=False, scattering=False, refraction=False,
                ripples=False, glints=False, compression=False)


@pytest.fixture(scope="module")
def small_clip(tmp_path_factory):
    out = tmp_path_factory.mktemp("clip")
    return make_clip(SMALL, out), out


def _truth(files):
    return json.loads(files.truth_json.read_text())


def test_clip_writes_video_masks_telemetry_and_truth(small_clip):
    """Every output exists, the video decodes with the configured size, rate and length."""
    files, _ = small_clip
    clip = open_clip(files.video)
    assert (clip.width_px, clip.height_px, clip.num_frames) == (320, 240, SMALL.num_frames)
    assert clip.fps == pytest.approx(5.0)
    assert len(list(files.masks_dir.glob("*.png"))) == SMALL.num_frames
    truth = _truth(files)
    assert len(truth["frames"]) == SMALL.num_frames
    assert np.asarray(truth["betas"]).shape == (11, 4)


def test_truth_is_self_consistent(small_clip):
    """Length is the configured one; mass and BCI follow from volume and length."""
    truth = _truth(small_clip[0])
    assert truth["length_m"] == pytest.approx(2.3, abs=1e-9)
    assert 0.010 < truth["volume_m3"] / truth["length_m"] ** 3 < 0.016
    condition = body_condition(np.float64(truth["length_m"]), np.float64(truth["volume_m3"]))
    assert truth["mass_kg"] == pytest.approx(float(condition.mass_kg), rel=1e-12)
    assert truth["bci"] == pytest.approx(float(condition.bci), rel=1e-12)


def test_same_seed_same_clip_other_seed_other_animal(small_clip, tmp_path):
    """A second run with the seed gives identical truth and masks; another seed differs."""
    files, _ = small_clip
    again = make_clip(SMALL, tmp_path / "again")
    assert again.truth_json.read_text() == files.truth_json.read_text()
    for name in ("000000.png", f"{SMALL.num_frames - 1:06d}.png"):
        assert (again.masks_dir / name).read_bytes() == (files.masks_dir / name).read_bytes()
    other = make_clip(replace(SMALL, seed=4, duration_s=0.2), tmp_path / "other")
    assert _truth(other)["volume_m3"] != _truth(files)["volume_m3"]


def test_progress_per_frame_and_cancel(tmp_path):
    """One report per rendered frame up to the last; a set cancel event raises Cancelled."""
    config = replace(SMALL, duration_s=0.4)
    reports = []
    make_clip(config, tmp_path / "watched", progress=reports.append)
    assert [(r.stage, r.step, r.total) for r in reports] == [
        ("render", k, config.num_frames) for k in range(1, config.num_frames + 1)]
    cancel = threading.Event()
    cancel.set()
    with pytest.raises(Cancelled):
        make_clip(config, tmp_path / "cancelled", cancel=cancel)
    assert not (tmp_path / "cancelled" / "truth.json").exists()


def test_telemetry_files_give_the_true_altitude(small_clip):
    """The SRT sidecar (with the launch height) and the CSV both give the truth's altitudes."""
    files, _ = small_clip
    truth_altitude = np.array([f["altitude_m"] for f in _truth(files)["frames"]])
    clip = open_clip(files.video)
    from_srt = load_telemetry(clip, launch_height_m=SMALL.launch_height_m)
    np.testing.assert_allclose(from_srt.altitude_m, truth_altitude, atol=1e-3)
    from_csv = load_telemetry(clip, files.altitude_csv)
    np.testing.assert_allclose(from_csv.altitude_m, truth_altitude, atol=1e-6)


def test_masks_match_the_true_geometry(tmp_path):
    """Without unmodelled effects, each mask is the hard silhouette of the true pose (IoU > 0.95)."""
    config = replace(SMALL, effects=PLAIN, noise_sd=0.0, blur_px=0.0)
    files = make_clip(config, tmp_path)
    truth = _truth(files)
    model = DolphinModel(load_template(), dtype=torch.float64)
    pose = torch.tensor([f["pose_aa"] for f in truth["frames"]], dtype=torch.float64)
    transl = torch.tensor([f["transl_m"] for f in truth["frames"]], dtype=torch.float64)
    verts = model(torch.tensor(truth["betas"], dtype=torch.float64), pose, transl).verts
    intrinsics = CameraIntrinsics.from_sensor(12.29, 17.27, 320, 240)
    camera = NadirCamera(intrinsics, torch.tensor([f["altitude_m"] for f in truth["frames"]],
                                                  dtype=torch.float64), refraction=False)
    xy, depth = project_to_viewport(verts, camera, Viewport.full_frame(intrinsics, len(pose)))
    coverage = rasterize(xy, depth, model.faces, 240, 320, 10**7).covered.numpy()
    for t in range(len(pose)):
        mask = cv2.imread(str(files.masks_dir / f"{t:06d}.png"), cv2.IMREAD_GRAYSCALE) > 0
        iou = (mask & coverage[t]).sum() / (mask | coverage[t]).sum()
        assert iou > 0.95
    assert files.video.suffix == ".mkv"


def test_true_masks_lie_on_the_outline(tmp_path):
    """The true mask is the pixels at least half covered, measured finely: against coverage
    counted on 8 × 8 points a pixel, its outline lies within 0.04 px on average (counting
    every half-covered pixel of the 2 × 2 supersampled scene in put it 0.03–0.21 px out)."""
    config = replace(SMALL, effects=PLAIN, noise_sd=0.0, blur_px=0.0, duration_s=0.6)
    files = make_clip(config, tmp_path)
    truth = _truth(files)
    model = DolphinModel(load_template(), dtype=torch.float64)
    frames = truth["frames"]
    pose = torch.tensor([f["pose_aa"] for f in frames], dtype=torch.float64)
    transl = torch.tensor([f["transl_m"] for f in frames], dtype=torch.float64)
    verts = model(torch.tensor(truth["betas"], dtype=torch.float64), pose, transl).verts
    fine = CameraIntrinsics.from_sensor(12.29, 17.27, 320 * 8, 240 * 8)
    camera = NadirCamera(fine, torch.tensor([f["altitude_m"] for f in frames],
                                            dtype=torch.float64), refraction=False)
    xy, depth = project_to_viewport(verts, camera, Viewport.full_frame(fine, len(pose)))
    covered = rasterize(xy, depth, model.faces, 240 * 8, 320 * 8, 10**8).covered.numpy()
    for t in range(len(pose)):
        exact = covered[t].reshape(240, 8, 320, 8).mean((1, 3)) >= 0.5
        mask = cv2.imread(str(files.masks_dir / f"{t:06d}.png"), cv2.IMREAD_GRAYSCALE) > 0
        assert abs(outline_offset_px(mask, exact)) < 0.04


def test_a_deep_dive_in_murky_water_hides_the_animal(tmp_path):
    """Frames where the animal is too deep to see are flagged invisible and get empty masks."""
    config = replace(SMALL, duration_s=2.0, dive_depth_m=4.0, clarity_per_m=(1.2, 0.9, 0.8))
    files = make_clip(config, tmp_path)
    frames = _truth(files)["frames"]
    visible = [f["visible"] for f in frames]
    assert visible[0] and not all(visible)
    for f in frames:
        mask = cv2.imread(str(files.masks_dir / f"{f['frame']:06d}.png"), cv2.IMREAD_GRAYSCALE)
        assert (mask.sum() > 0) == f["visible"]


def test_finer_mesh_keeps_the_animal_close_to_its_template(tmp_path):
    """A Loop-subdivided animal has nearly the same volume and length."""
    coarse = make_clip(replace(SMALL, duration_s=0.2, effects=replace(PLAIN, compression=True)),
                       tmp_path / "coarse")
    fine = make_clip(replace(SMALL, duration_s=0.2,
                             effects=replace(PLAIN, compression=True, finer_mesh=True)),
                     tmp_path / "fine")
    assert _truth(fine)["volume_m3"] == pytest.approx(_truth(coarse)["volume_m3"], rel=0.01)
    assert _truth(fine)["length_m"] == pytest.approx(2.3, abs=1e-9)


def test_config_round_trips_and_rejects_nonsense():
    """JSON round trip is exact; bad values and unknown keys are input errors."""
    assert SynthConfig.from_json(json.loads(json.dumps(SMALL.to_json()))) == SMALL
    with pytest.raises(InputError, match="altitude_m"):
        replace(SMALL, altitude_m=-3.0)
    with pytest.raises(InputError, match="even"):
        replace(SMALL, width_px=321)
    with pytest.raises(InputError, match="unknown"):
        SynthConfig.from_json({"altitude": 20})


def test_cli_makes_a_clip_and_reproduces_it_from_its_truth(tmp_path, capsys):
    """`dolphinfit synth` writes a clip; feeding its truth.json back as --config repeats it."""
    args = ["--seed", "5", "--width-px", "160", "--height-px", "120", "--fps", "5",
            "--duration-s", "0.4", "--altitude-m", "5", "--no-glints", "--water-rgb", "0.1,0.3,0.3"]
    assert main(["synth", str(tmp_path / "a"), *args]) == 0
    truth = json.loads((tmp_path / "a" / "truth.json").read_text())
    assert truth["config"]["effects"]["glints"] is False
    assert truth["config"]["water_rgb"] == [0.1, 0.3, 0.3]
    assert main(["synth", str(tmp_path / "b"), "--config", str(tmp_path / "a" / "truth.json")]) == 0
    assert (tmp_path / "b" / "truth.json").read_text() == (tmp_path / "a" / "truth.json").read_text()
    assert main(["synth", str(tmp_path / "c"), "--sea-state", "2"]) == 2


def test_sample_is_made_once_and_reused(tmp_path, monkeypatch):
    """The sample clip is rendered into the cache on first use and reused after."""
    monkeypatch.setenv(sample.CACHE_DIR_ENV, str(tmp_path))
    monkeypatch.setattr(sample, "SAMPLE_CONFIG", replace(SMALL, duration_s=0.4))
    first = sample.ensure_sample()
    stamp = first.truth_json.stat().st_mtime_ns
    second = sample.ensure_sample()
    assert second.truth_json == first.truth_json
    assert second.truth_json.stat().st_mtime_ns == stamp


def test_body_contrast_scales_the_animal_against_the_water(tmp_path):
    """Half the body contrast halves the animal's difference from the water behind it (the
    frame's other pixels stay), and the default draws the clip as before, to the bit."""
    config = replace(SMALL, effects=PLAIN, noise_sd=0.0, blur_px=0.0, duration_s=0.4)
    plain = make_clip(config, tmp_path / "plain")
    again = make_clip(replace(config, body_contrast=1.0), tmp_path / "again")
    half = make_clip(replace(config, body_contrast=0.5), tmp_path / "half")
    with VideoReader(open_clip(plain.video)) as a, VideoReader(open_clip(again.video)) as b, \
            VideoReader(open_clip(half.video)) as c:
        mask = cv2.imread(str(plain.masks_dir / "000000.png"), cv2.IMREAD_GRAYSCALE) > 0
        assert np.array_equal(a[0], b[0])
        outside = ~cv2.dilate(mask.astype(np.uint8), np.ones((9, 9), np.uint8)).astype(bool)
        assert np.abs(a[0].astype(int) - c[0].astype(int))[outside].max() <= 1
        water = np.median(a[0][outside], axis=0)
        full = np.abs(a[0][mask] - water).mean()
        halved = np.abs(c[0][mask].astype(float) - water).mean()
        assert halved == pytest.approx(full / 2, rel=0.1)


def test_h264_at_a_constant_rate_factor(tmp_path):
    """A higher CRF writes a smaller file; both decode to the clip's frames."""
    config = replace(SMALL, codec="h264", duration_s=0.6)
    sizes = {}
    for crf in (18, 35):
        files = make_clip(replace(config, crf=crf), tmp_path / str(crf))
        sizes[crf] = files.video.stat().st_size
        assert open_clip(files.video).num_frames == config.num_frames
    assert sizes[35] < sizes[18] / 2
    with pytest.raises(InputError, match="crf"):
        replace(config, crf=60)
