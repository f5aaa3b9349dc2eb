"""Training windows for the edge network, from synthetic clips drawn at random.

``training_configs`` draws clips over a wider range than the bench suite shows (water colour
and clarity jittered around each preset, dark and light-grey animals of 1.7–3.0 m from 12–30 m,
glitter, splash, companions alongside and touching, turns, deep passes, sections and heights
varied); none uses a suite seed. ``clip_windows`` renders each clip once into the cache and
cuts, from every frame where the target is visible, the window the tracker would look at:
around the true mask moved by a random motion error, grown as the tracker grows it, with the
salient network's probability and the component the tracker would choose
(``NetLook.masked_in``), and the true mask in that window as the target.
"""

import math
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.io.masks import read_png_folder
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET
from dolphinfit.core.segment.net_settings import NetSettings
from dolphinfit.core.segment.net_look import NetLook
from dolphinfit.core.segment.regions import centroid, shifted
from dolphinfit.core.segment.salient import SalientNet
from dolphinfit.core.segment.seed import dilate
from dolphinfit.core.segment.windows import longer_side, square_window, window_side
from dolphinfit.core.synth.config import Effects, SynthConfig
from dolphinfit.core.synth.files import ClipFiles
from dolphinfit.core.synth.sample import ensure_clip
from dolphinfit.core.synth.water import WATER_PRESETS, with_water

TRAINING_SET = "edge-training-v1"
FIRST_SEED = 100_000     # far from the suite's seeds (201–212) and the sample's (7)
HARD_FIRST_SEED = 200_000
HARD_SCENES = ("surfacing", "glitter", "faint", "dark_over_bed")
COLOURATION_P_DARK = 0.35
GROWTH_RANGE = (0.85, 2.2)   # window side × the tracker's (seed rounds and lost frames grow it)
MOTION_ERROR = 0.06          # SD of the prediction's offset, × the animal's length
MIN_PRIOR_SHARE = 0.3        # a window's prior covers at least this of its true mask
WINDOWS_PER_FRAME = 2        # each with its own motion error and window
# how windows are cut (recorded with each clip's windows; change it when the cutting changes)
WINDOW_RECIPE = {"growth": GROWTH_RANGE, "motion_error": MOTION_ERROR,
                 "min_prior_share": MIN_PRIOR_SHARE, "per_frame": WINDOWS_PER_FRAME}


def training_configs(count: int, seed: int = 0, hard: int = 0) -> list[SynthConfig]:
    """``count`` random clips (module doc) and ``hard`` clips of the scenes where outlines are
    hardest (``HARD_SCENES``), the same for the same ``seed``; each family has its own
    random stream, so adding hard clips leaves the others as they were."""
    rng = np.random.default_rng([seed, 17])
    general = [_random_config(rng, FIRST_SEED + 1000 * seed + index) for index in range(count)]
    rng = np.random.default_rng([seed, 19])
    return general + [_hard_config(rng, HARD_FIRST_SEED + 1000 * seed + index)
                      for index in range(hard)]


def _hard_config(rng: np.random.Generator, clip_seed: int) -> SynthConfig:
    scene = HARD_SCENES[int(rng.integers(len(HARD_SCENES)))]
    water = {"faint": "murky", "dark_over_bed": "sandy"}.get(scene)
    config = _random_config(rng, clip_seed, water)
    if scene == "surfacing":   # the body breaks the surface in white water
        return replace(config, surface_depth_m=float(rng.uniform(0.0, 0.04)),
                       dive_depth_m=float(rng.uniform(0.0, 0.3)),
                       splash=float(rng.uniform(0.6, 1.0)), speed_m_s=float(rng.uniform(2, 3)))
    if scene == "glitter":     # the sun's glitter path crosses the animal
        return replace(config, glitter=float(rng.uniform(0.7, 1.0)),
                       sea_state=float(rng.uniform(0.35, 0.6)),
                       sun_elevation_deg=float(rng.uniform(65, 80)), colouration="light_grey")
    if scene == "faint":       # a pass half a metre down or more in turbid water
        return replace(config, surface_depth_m=float(rng.uniform(0.3, 0.7)),
                       dive_depth_m=float(rng.uniform(0.2, 0.8)), splash=0.0)
    return replace(config, colouration="dark", seabed_cover=float(rng.uniform(0.3, 0.6)))


def _random_config(rng: np.random.Generator, clip_seed: int,
                   water: str | None = None) -> SynthConfig:
    water = rng.choice(sorted(WATER_PRESETS)) if water is None else water
    preset = WATER_PRESETS[water]

    def jitter(values: tuple[float, ...], spread: float) -> tuple[float, ...]:
        return tuple(float(v * math.exp(rng.normal(0, spread))) for v in values)

    turning = rng.random() < 0.4
    companion = rng.random() < 0.4
    splash_kind = rng.random()
    config = SynthConfig(
        seed=clip_seed, width_px=1920, height_px=1080, fps=3.0, duration_s=3.0,
        altitude_m=float(rng.uniform(12.0, 30.0)), length_m=float(rng.uniform(1.7, 3.0)),
        shape_sd=0.05, speed_m_s=float(rng.uniform(0.8, 2.8)),
        heading_deg=float(rng.uniform(-180, 180)),
        turn_deg_s=float(rng.choice([-1, 1]) * (rng.uniform(20, 55) if turning
                                               else rng.uniform(0, 8))),
        turn_flex=float(rng.uniform(0.5, 1.0)) if turning else 0.0,
        stroke_amplitude=float(rng.uniform(0.6, 1.4)),
        surface_depth_m=float(rng.uniform(0.02, 0.5)), dive_depth_m=float(rng.uniform(0, 0.9)),
        roll_deg=float(rng.uniform(0, 10)),
        sea_state=float(rng.uniform(0.0, 0.6)),
        sun_elevation_deg=float(rng.uniform(35, 80)), sun_azimuth_deg=float(rng.uniform(0, 360)),
        noise_sd=float(rng.uniform(0.006, 0.02)), blur_px=float(rng.uniform(0.4, 1.0)),
        colouration="dark" if rng.random() < COLOURATION_P_DARK else "light_grey",
        glitter=0.0 if rng.random() < 0.5 else float(rng.uniform(0.1, 1.0)),
        wet_specular=float(rng.uniform(0, 0.5)),
        splash=(0.0 if splash_kind < 0.2 else float(rng.uniform(0, 0.3)) if splash_kind < 0.8
                else float(rng.uniform(0.5, 1.0))),
        companion_offset_m=(float(rng.choice([-1, 1]) * rng.uniform(0.45, 2.0)) if companion
                            else None),
        companion_ahead_m=float(rng.uniform(-1.0, 1.0)),
        companion_length_m=float(rng.uniform(1.9, 2.8)),
        hw_table=DEFAULT_PRESET if rng.random() < 0.6 else None,
        section_exponent=float(rng.uniform(1.8, 2.2)),
        effects=Effects(finer_mesh=bool(rng.random() < 0.5)))
    config = with_water(config, str(water))
    changes = dict(water_rgb=jitter(preset["water_rgb"], 0.2),
                   clarity_per_m=jitter(preset["clarity_per_m"], 0.3))
    if config.seabed_depth_m is not None:
        changes.update(seabed_depth_m=float(rng.uniform(1.5, 4.0)),
                       seabed_cover=float(rng.uniform(0.1, 0.6)),
                       seabed_rgb=tuple(float(np.clip(v, 0, 1))
                                        for v in jitter(config.seabed_rgb, 0.15)))
    return replace(config, **changes)


@dataclass(frozen=True)
class Window:
    """One training window: what the outline step sees and the truth there."""

    crop_rgb: np.ndarray     # (h, w, 3) uint8
    saliency: np.ndarray     # (h, w) uint8, probability × 255
    prior: np.ndarray        # (h, w) bool: the tracker's chosen component
    target: np.ndarray       # (h, w) bool: the true mask


WINDOW_ARRAYS = tuple(field.name for field in fields(Window))  # as saved, in order


class _Recorder:
    """An outline step that keeps what it was given and changes nothing."""

    name = "recorder"

    def __init__(self) -> None:
        self.seen: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    def __call__(self, crop_rgb: np.ndarray, saliency: np.ndarray,
                 mask: np.ndarray) -> np.ndarray:
        self.seen = (crop_rgb, saliency, mask)
        return mask


def training_clip(config: SynthConfig, root: Path) -> ClipFiles:
    """The clip of ``config`` under ``root`` (its seed names the folder), rendered if missing."""
    return ensure_clip(config, root / f"clip_{config.seed}")


def clip_windows(files: ClipFiles, seed: int, net: SalientNet | None = None) -> list[Window]:
    """At most one window per frame where the target is visible (module doc): none where
    the tracker's component would miss the target (``MIN_PRIOR_SHARE``)."""
    rng = np.random.default_rng([seed, 23])
    recorder = _Recorder()
    look = NetLook(NetSettings(), net=net, edges=recorder)
    clip = open_clip(files.video)
    truth = read_png_folder(files.masks_dir, clip)
    windows = []
    with VideoReader(clip) as frames:
        for frame_idx in range(clip.num_frames):
            if not truth.is_visible[frame_idx]:
                continue
            target = truth.mask(frame_idx)
            window = _window(look, recorder, frames[frame_idx], target, rng)
            if window is not None:
                windows.append(window)
    return windows


def _window(look: NetLook, recorder: _Recorder, frame_rgb: np.ndarray,
            target: np.ndarray, rng: np.random.Generator) -> Window | None:
    length_px = longer_side(target)
    prediction = shifted(target, rng.normal(0, MOTION_ERROR * length_px, 2))
    if not prediction.any():
        return None
    growth = math.exp(rng.uniform(*np.log(GROWTH_RANGE)))
    side = window_side(length_px, look.settings, growth)
    rows, cols = square_window(centroid(prediction) + rng.normal(0, 0.05 * side, 2), side,
                               *frame_rgb.shape[:2])
    moving = rng.random() < 0.7
    focus = (dilate(prediction, round(look.settings.focus_fraction * length_px)) if moving
             else None)
    recorder.seen = None
    look.masked_in(frame_rgb, rows, cols, prediction, near=bool(rng.random() < 0.8),
                      focus=focus)
    if recorder.seen is None:
        return None
    crop, saliency, prior = recorder.seen
    truth = target[rows, cols]
    if not truth.any() or \
            np.count_nonzero(prior & truth) < MIN_PRIOR_SHARE * np.count_nonzero(truth):
        return None  # the tracker would follow another animal or nothing here
    return Window(crop.copy(), np.round(saliency * 255).astype(np.uint8), prior.copy(),
                  truth.copy())


def save_windows(windows: list[Window], path: Path) -> None:
    """The windows of one clip in one ``.npz``."""
    arrays = {}
    for index, window in enumerate(windows):
        for name in WINDOW_ARRAYS:
            arrays[f"{name}_{index:04d}"] = getattr(window, name)
    with atomic_path(path) as temporary:
        with open(temporary, "wb") as stream:
            np.savez_compressed(stream, count=np.array(len(windows)), **arrays)


def load_windows(path: Path) -> list[Window]:
    """The windows ``save_windows`` wrote."""
    with np.load(path, allow_pickle=False) as data:
        return [Window(*(data[f"{name}_{index:04d}"] for name in WINDOW_ARRAYS))
                for index in range(int(data["count"]))]
