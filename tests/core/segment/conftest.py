"""Synthetic drone clips of a dolphin-like animal with exact true masks, drawn with OpenCV.

Until core/synth renders the parametric model, these clips measure the tracker: a dark,
elongated, textured body with flippers and foreshortening flukes swims a turning path over a
blue-green sea. "calm" water has a slow texture and sensor noise; "rough" water adds moving
waves over everything, sun glints (over the animal too) and more noise; "dive" clips fade the
animal out (frames 18–28), keep it under (28–36) and bring it back (36–42). Frames are drawn
4× supersampled, so outlines are antialiased, and saved as lossy mp4v. The true mask is the
animal's coverage ≥ 0.5 wherever its opacity is ≥ 0.5, else empty.
"""

from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.core.io.masks import MaskTrack, write_masks

WIDTH_PX, HEIGHT_PX, NUM_FRAMES, FPS = 320, 240, 48, 25.0
SUPERSAMPLE = 4
LENGTH_PX = 110.0  # rostrum to fluke notch, about a 2.5 m animal at 1920 px and 30 m altitude
MAX_HALF_WIDTH = 0.11  # × length
WATER_BGR = np.array([120.0, 104.0, 38.0])  # blue-green sea
BACK_BGR = np.array([66.0, 66.0, 62.0])  # dark grey back
FLANK_BGR = np.array([112.0, 116.0, 110.0])  # lighter flanks (countershading)
VISIBLE_OPACITY = 0.5


@dataclass(frozen=True)
class Sea:
    """How the water looks: texture and noise SDs (grey levels), waves, glints per frame."""

    texture_sd: float
    noise_sd: float
    wave_amplitude: float  # relative brightness modulation of the surface
    glints: int


SEAS = {"calm": Sea(6.0, 3.0, 0.0, 0), "rough": Sea(10.0, 7.0, 0.16, 45)}


def _opacity(frame_idx: int, dive: bool) -> float:
    """1 at the surface; fades to 0 over frames 18–28, under until 36, back by 42."""
    if not dive:
        return 1.0
    return float(np.interp(frame_idx, [18, 28, 36, 42], [1.0, 0.0, 0.0, 1.0]))


def _outline(center: np.ndarray, heading_rad: float, bend: float, fluke_scale: float):
    """Polygons (body, two flippers, flukes) in pixels: (N, 2) float arrays."""
    s = np.linspace(0.0, 1.0, 60)  # 0 rostrum, 1 fluke notch
    half = MAX_HALF_WIDTH * np.sin(np.pi * np.clip(s, 0, 1) ** 0.75) ** 0.9 + 0.012
    half = np.where(s > 0.85, half * (1.0 - (s - 0.85) * 3.0), half)
    axis_x = (0.45 - s) * LENGTH_PX
    axis_y = bend * (s - 0.35) ** 2 * LENGTH_PX
    normal_sign = np.array([1.0, -1.0])

    def world(x, y):
        c, si = np.cos(heading_rad), np.sin(heading_rad)
        return np.stack([center[0] + c * x - si * y, center[1] + si * x + c * y], axis=-1)

    slope = np.gradient(axis_y, axis_x)
    nx, ny = -slope / np.hypot(1, slope), 1 / np.hypot(1, slope)
    left = world(axis_x + nx * half * LENGTH_PX, axis_y + ny * half * LENGTH_PX)
    right = world(axis_x - nx * half * LENGTH_PX, axis_y - ny * half * LENGTH_PX)
    body = np.concatenate([left, right[::-1]])
    flippers = []
    for sign in normal_sign:
        base = 0.3
        x0, y0 = (0.45 - base) * LENGTH_PX, bend * (base - 0.35) ** 2 * LENGTH_PX
        w = (MAX_HALF_WIDTH + 0.01) * LENGTH_PX
        flippers.append(world(np.array([x0 + 4, x0 - 8, x0 - 16]),
                              np.array([y0 + sign * w * 0.7, y0 + sign * (w + 10),
                                        y0 + sign * (w + 14)])))
    tail_x, tail_y = -0.55 * LENGTH_PX, bend * 0.65 ** 2 * LENGTH_PX
    span, chord = 0.15 * LENGTH_PX, 0.11 * LENGTH_PX * fluke_scale
    flukes = world(np.array([tail_x + 6, tail_x - chord, tail_x - chord * 0.55, tail_x - 2,
                             tail_x - chord * 0.55, tail_x - chord]),
                   np.array([tail_y, tail_y + span, tail_y + span * 0.35, tail_y,
                             tail_y - span * 0.35, tail_y - span]))
    return [body, *flippers, flukes]


def _coverage(polygons) -> np.ndarray:
    """(H, W) float32 coverage fraction of the polygons, 4× supersampled."""
    canvas = np.zeros((HEIGHT_PX * SUPERSAMPLE, WIDTH_PX * SUPERSAMPLE), np.uint8)
    shift = 4
    scale = SUPERSAMPLE * (1 << shift)
    for polygon in polygons:
        points = np.round((polygon + 0.5) * scale - (1 << shift) / 2).astype(np.int32)
        cv2.fillPoly(canvas, [points], 255, lineType=cv2.LINE_8, shift=shift)
    return cv2.resize(canvas.astype(np.float32) / 255, (WIDTH_PX, HEIGHT_PX),
                      interpolation=cv2.INTER_AREA)


def _smooth_noise(rng, shape, sigma_px: float) -> np.ndarray:
    """Unit-SD smooth noise of the given correlation length."""
    noise = cv2.GaussianBlur(rng.standard_normal(shape).astype(np.float32), (0, 0), sigma_px)
    return noise / noise.std()


def _add_glint(frame: np.ndarray, x: float, y: float, radius_px: float) -> None:
    """Add a small bright Gaussian spot (a sun glint) to a float frame, in place."""
    col0, row0 = max(0, int(x) - 6), max(0, int(y) - 6)
    rows, cols = np.mgrid[row0:min(HEIGHT_PX, int(y) + 7), col0:min(WIDTH_PX, int(x) + 7)]
    spot = np.exp(-((cols - x) ** 2 + (rows - y) ** 2) / (2 * radius_px**2))
    frame[rows, cols] += 170.0 * spot[..., None]


def render_clip(sea: Sea, dive: bool, seed: int = 0):
    """Frames (T, H, W, 3) uint8 BGR and true masks (T, H, W) bool."""
    rng = np.random.default_rng(seed)
    water_texture = _smooth_noise(rng, (HEIGHT_PX + 64, WIDTH_PX + 64), 9.0)
    skin = _smooth_noise(rng, (HEIGHT_PX, WIDTH_PX), 2.0)
    rows, cols = np.mgrid[0:HEIGHT_PX, 0:WIDTH_PX].astype(np.float32)
    frames, masks = [], []
    for t in range(NUM_FRAMES):
        heading = 0.15 + 0.014 * t
        center = np.array([85.0, 75.0]) + np.array([np.cos(heading), np.sin(heading)]) * 3.0 * t
        bend = 0.25 * np.sin(0.15 * t)
        fluke_scale = 0.65 + 0.35 * np.cos(2 * np.pi * t / 12)
        coverage = _coverage(_outline(center, heading, bend, fluke_scale))
        opacity = _opacity(t, dive)
        interior = cv2.GaussianBlur(coverage, (0, 0), 4.0)
        shade = np.clip((interior - 0.25) / 0.5, 0, 1)[..., None]
        animal = FLANK_BGR + (BACK_BGR - FLANK_BGR) * shade + 6.0 * skin[..., None]
        shift = (t * 1.3) % 64
        water = WATER_BGR + sea.texture_sd * water_texture[
            int(shift):int(shift) + HEIGHT_PX, 16:16 + WIDTH_PX, None]
        alpha = (coverage * opacity)[..., None]
        frame = water * (1 - alpha) + animal * alpha
        if sea.wave_amplitude:
            waves = (np.sin(cols / 7.0 + rows / 11.0 - 0.6 * t)
                     + 0.6 * np.sin(rows / 5.0 - cols / 17.0 + 0.4 * t))
            frame *= (1.0 + sea.wave_amplitude * waves / 1.6)[..., None]
        for _ in range(sea.glints):
            _add_glint(frame, rng.uniform(0, WIDTH_PX), rng.uniform(0, HEIGHT_PX),
                       rng.uniform(0.7, 1.8))
        frame += rng.normal(0.0, sea.noise_sd, frame.shape)
        frames.append(np.clip(frame, 0, 255).astype(np.uint8))
        masks.append((coverage >= 0.5) & (opacity >= VISIBLE_OPACITY))
    return np.stack(frames), np.stack(masks)


def write_clip(folder: Path, sea_name: str, dive: bool, seed: int = 0) -> tuple[Path, Path]:
    """Render a clip into ``folder``: (clip.mp4 path, true masks folder)."""
    frames, masks = render_clip(SEAS[sea_name], dive, seed)
    clip_path = folder / "clip.mp4"
    writer = cv2.VideoWriter(str(clip_path), cv2.VideoWriter_fourcc(*"mp4v"), FPS,
                             (WIDTH_PX, HEIGHT_PX))
    for frame in frames:
        writer.write(frame)
    writer.release()
    write_masks(MaskTrack.from_array(masks, "synthetic truth"), folder / "true_masks")
    return clip_path, folder / "true_masks"


CLIP_KINDS = {"calm": ("calm", False), "rough": ("rough", False),
              "calm-dive": ("calm", True), "rough-dive": ("rough", True)}


@pytest.fixture(scope="session")
def synthetic_clips(tmp_path_factory) -> dict[str, tuple[Path, Path]]:
    """The four synthetic clips, by kind: (clip path, true masks folder)."""
    clips = {}
    for kind, (sea_name, dive) in CLIP_KINDS.items():
        clips[kind] = write_clip(tmp_path_factory.mktemp(kind), sea_name, dive)
    return clips
