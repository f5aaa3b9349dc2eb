"""Synthetic clips that look like real water: colouration, water presets, glitter, a second
animal, part masks, seed points and turning bodies."""

import json
from dataclasses import replace

import cv2
import numpy as np
import pytest

from dolphinfit.app.cli import main
from dolphinfit.core.io.video import open_clip
from dolphinfit.core.synth.clip import make_clip
from dolphinfit.core.synth.config import Effects, SynthConfig
from dolphinfit.core.synth.files import read_part_masks
from dolphinfit.core.synth.water import with_water

SMALL = SynthConfig(seed=5, width_px=320, height_px=240, fps=5.0, duration_s=0.6,
                    altitude_m=6.0, length_m=2.3, heading_deg=30.0, speed_m_s=1.0,
                    dive_depth_m=0.0)
PLAIN = Effects(profile_warp=False, finer_mesh=False, scattering=True, refraction=False,
                ripples=False, glints=False, compression=False)


def _truth(files) -> dict:
    return json.loads(files.truth_json.read_text())


def _mask(files, t: int) -> np.ndarray:
    return cv2.imread(str(files.masks_dir / f"{t:06d}.png"), cv2.IMREAD_GRAYSCALE) > 0


def _frame(files, t: int) -> np.ndarray:
    capture = cv2.VideoCapture(str(files.video))
    for _ in range(t + 1):
        ok, frame = capture.read()
        assert ok
    return frame.astype(np.float64)


@pytest.fixture(scope="module")
def grey_pair(tmp_path_factory):
    """A light-grey animal over green water with a second one touching its left flank."""
    config = with_water(replace(SMALL, colouration="light_grey", companion_offset_m=0.5,
                                companion_ahead_m=-0.3, wet_specular=0.5, splash=0.5), "green")
    return make_clip(config, tmp_path_factory.mktemp("pair")), config


def test_light_grey_animal_is_lighter_than_green_water(grey_pair):
    """The light-grey animal's mean brightness exceeds the water's; the mp4v clip reads back
    with every frame."""
    files, config = grey_pair
    assert open_clip(files.video).num_frames == config.num_frames
    frame, mask = _frame(files, 1), _mask(files, 1)
    ring = cv2.dilate(mask.astype(np.uint8), np.ones((25, 25), np.uint8)) > 0
    water = ring & ~mask
    water &= ~(cv2.dilate(mask.astype(np.uint8), np.ones((9, 9), np.uint8)) > 0)
    animal = frame[mask].mean(0)
    background = frame[water].mean(0)
    assert animal.mean() > background.mean() + 20          # 8-bit levels
    assert background[1] > background[0]                   # green water (BGR)


def test_companion_stays_out_of_the_target_mask(grey_pair, tmp_path):
    """The target's mask with a companion beside it is its mask alone, less at most what the
    companion hides; the companion's body centre is never inside it; seed points are inside."""
    files, config = grey_pair
    alone = make_clip(replace(config, companion_offset_m=None), tmp_path)
    truth = _truth(files)
    focal_px = config.focal_mm / config.sensor_width_mm * config.width_px
    for frame in truth["frames"]:
        t = frame["frame"]
        with_mate, by_itself = _mask(files, t), _mask(alone, t)
        assert not (with_mate & ~by_itself).any()
        x, y, _ = frame["companion_transl_m"]
        col = int(round((config.width_px - 1) / 2 + x * focal_px / frame["altitude_m"]))
        row = int(round((config.height_px - 1) / 2 - y * focal_px / frame["altitude_m"]))
        assert not with_mate[row, col]
        seed_x, seed_y = frame["seed_px"]
        assert with_mate[seed_y, seed_x]


def test_part_masks_lie_in_the_true_mask_at_the_body_ends(grey_pair):
    """parts.npz holds (T, H, W) flukes and rostrum regions inside the true mask, at opposite
    ends of the body."""
    files, config = grey_pair
    parts = read_part_masks(files.parts)
    assert set(parts) == {"flukes", "rostrum"}
    shape = (config.num_frames, config.height_px, config.width_px)
    focal_px = config.focal_mm / config.sensor_width_mm * config.width_px
    for t in range(config.num_frames):
        mask = _mask(files, t)
        near = cv2.dilate(mask.astype(np.uint8), np.ones((5, 5), np.uint8)) > 0   # ± 2 px
        flukes, rostrum = parts["flukes"][t], parts["rostrum"][t]
        assert flukes.shape == shape[1:] and flukes.any() and rostrum.any()
        assert not (flukes & ~near).any() and not (rostrum & ~near).any()
        apart = np.linalg.norm(np.argwhere(flukes).mean(0) - np.argwhere(rostrum).mean(0))
        length_px = config.length_m * focal_px / _truth(files)["frames"][t]["altitude_m"]
        assert apart > 0.75 * length_px


def _midline_bend(mask: np.ndarray) -> float:
    """Largest offset of the silhouette's midline from its chord, as a fraction of its length:
    pixels binned along the principal axis, mean perpendicular offset per bin."""
    points = np.argwhere(mask).astype(np.float64)
    centred = points - points.mean(0)
    _, _, axes = np.linalg.svd(centred, full_matrices=False)
    along, across = centred @ axes[0], centred @ axes[1]
    bins = np.linspace(along.min(), along.max(), 13)
    which = np.digitize(along, bins[1:-1])
    offsets = np.array([across[which == k].mean() for k in range(12)])
    chord = np.linspace(offsets[0], offsets[-1], 12)
    return float(np.abs(offsets - chord).max() / (along.max() - along.min()))


def test_turning_body_bends_with_the_turn(tmp_path):
    """In a 50°/s turn with lateral flex, the silhouette's midline bends far more than the
    same turn with a straight body."""
    config = replace(SMALL, duration_s=0.2, turn_deg_s=50.0, effects=PLAIN, noise_sd=0.0)
    bent = make_clip(replace(config, turn_flex=1.0), tmp_path / "bent")
    straight = make_clip(config, tmp_path / "straight")
    assert _midline_bend(_mask(bent, 0)) > 0.06
    assert _midline_bend(_mask(bent, 0)) > 3 * _midline_bend(_mask(straight, 0))


def test_sandy_shallows_and_glitter_change_the_water(tmp_path):
    """A sandy bed with seagrass makes the water patchy; glitter adds saturated sparkles."""
    config = replace(SMALL, duration_s=0.2, noise_sd=0.0)
    open_water = _frame(make_clip(config, tmp_path / "open"), 0)
    sandy = _frame(make_clip(with_water(config, "sandy"), tmp_path / "sandy"), 0)
    assert sandy.std(axis=(0, 1)).mean() > 1.5 * open_water.std(axis=(0, 1)).mean()
    sparkly = _frame(make_clip(replace(config, glitter=1.0, sun_elevation_deg=80.0),
                               tmp_path / "glitter"), 0)
    assert (sparkly.max(-1) >= 250).sum() > 20 + (open_water.max(-1) >= 250).sum()


def test_cli_sets_water_presets_and_new_options(tmp_path):
    """`--water` fills the water options; new options are recorded in truth.json."""
    args = ["--seed", "2", "--width-px", "160", "--height-px", "120", "--fps", "5",
            "--duration-s", "0.2", "--altitude-m", "5", "--water", "sandy",
            "--colouration", "light_grey", "--glitter", "0.5", "--turn-flex", "1",
            "--companion-offset-m", "0.8", "--clarity-per-m", "0.3,0.1,0.1"]
    assert main(["synth", str(tmp_path / "a"), *args]) == 0
    config = json.loads((tmp_path / "a" / "truth.json").read_text())["config"]
    assert config["seabed_depth_m"] == 2.5 and config["colouration"] == "light_grey"
    assert config["clarity_per_m"] == [0.3, 0.1, 0.1]
    assert config["companion_offset_m"] == 0.8 and config["glitter"] == 0.5
    assert main(["synth", str(tmp_path / "b"), "--colouration", "pink"]) == 2
