"""A procedural sea seen from above: water colour, waves, sky reflection and sun glints.

The surface is a sum of directional deep-water waves (ω² = g·k) whose height η(x, y, t) and
slopes are evaluated in world metres on the water plane, at half the image resolution and
upsampled. Facets tilted towards the sun look brighter; glints appear where a facet mirrors the
sun into the camera (a sharp lobe about the half vector).
"""

import math
from dataclasses import dataclass

import cv2
import numpy as np

from core.synth.config import SynthConfig

GRAVITY_M_S2 = 9.81
NUM_WAVES = 10
SKY_RGB = np.array([0.55, 0.65, 0.78])
SKY_REFLECTANCE = 0.025      # Fresnel reflectance of water near normal incidence
GLINT_SHARPNESS = 900.0      # exp(κ(n·h − 1)) lobe of the glints
COLOUR_VARIATION = 0.06      # relative low-frequency patchiness of the water colour


@dataclass(frozen=True)
class WaveField:
    """Directional wave components (world frame, metres, seconds)."""

    wavenumber: np.ndarray   # (K, 2) k vectors, rad/m
    amplitude_m: np.ndarray  # (K,)
    omega: np.ndarray        # (K,) angular frequency, rad/s
    phase: np.ndarray        # (K,)


@dataclass(frozen=True)
class SeaFrame:
    """One frame of sea: the water image and the surface slopes under each pixel."""

    rgb: np.ndarray          # (H, W, 3) float32 water colour without glints
    glints: np.ndarray       # (H, W) float32 glint intensity, added on top of everything
    slope: np.ndarray        # (H, W, 2) float32 ∂η/∂x, ∂η/∂y


class Sea:
    """The sea of one clip: fixed waves and colour patches, evaluated frame by frame."""

    def __init__(self, config: SynthConfig, rng: np.random.Generator):
        self.config = config
        self.waves = _random_waves(config.sea_state, rng)
        coarse = rng.normal(0.0, 1.0, size=(config.height_px // 48 + 2, config.width_px // 48 + 2))
        patches = cv2.resize(coarse.astype(np.float32), (config.width_px, config.height_px),
                             interpolation=cv2.INTER_CUBIC)
        self.colour = (np.asarray(config.water_rgb, dtype=np.float32)
                       * (1.0 + COLOUR_VARIATION * patches[..., None]))
        self.sun = config.sun_direction()

    def frame(self, time_s: float, altitude_m: float) -> SeaFrame:
        """The sea at ``time_s`` seen from ``altitude_m`` (camera over the world origin)."""
        cfg = self.config
        half_w, half_h = cfg.width_px // 2, cfg.height_px // 2
        focal_px = cfg.focal_mm / cfg.sensor_width_mm * cfg.width_px
        cols = (np.arange(half_w) * 2 + 0.5 - (cfg.width_px - 1) / 2) * altitude_m / focal_px
        rows = ((cfg.height_px - 1) / 2 - (np.arange(half_h) * 2 + 0.5)) * altitude_m / focal_px
        x, y = np.meshgrid(cols, rows)
        slope_x, slope_y = _wave_slopes(self.waves, x, y, time_s)
        normal = np.stack([-slope_x, -slope_y, np.ones_like(x)], -1)
        normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
        to_camera = np.stack([-x, -y, np.full_like(x, altitude_m)], -1)
        to_camera /= np.linalg.norm(to_camera, axis=-1, keepdims=True)
        halfway = to_camera + self.sun
        halfway /= np.linalg.norm(halfway, axis=-1, keepdims=True)
        glint = np.exp(GLINT_SHARPNESS * ((normal * halfway).sum(-1) - 1.0))
        lit = 1.0 + 2.0 * (slope_x * self.sun[0] + slope_y * self.sun[1])

        size = (cfg.width_px, cfg.height_px)
        lit = cv2.resize(lit.astype(np.float32), size, interpolation=cv2.INTER_LINEAR)
        rgb = self.colour * lit[..., None] + SKY_REFLECTANCE * SKY_RGB.astype(np.float32)
        return SeaFrame(
            rgb=rgb,
            glints=cv2.resize(glint.astype(np.float32), size, interpolation=cv2.INTER_LINEAR),
            slope=cv2.resize(np.stack([slope_x, slope_y], -1).astype(np.float32), size,
                             interpolation=cv2.INTER_LINEAR),
        )


def _random_waves(sea_state: float, rng: np.random.Generator) -> WaveField:
    """Waves from a main wind direction, 0.2–4 m long, steeper as the sea roughens."""
    wind = rng.uniform(0, 2 * math.pi)
    directions = wind + rng.normal(0.0, 0.6, NUM_WAVES)
    wavelength = np.exp(rng.uniform(math.log(0.2), math.log(4.0), NUM_WAVES))
    k = 2 * math.pi / wavelength
    steepness = 0.015 + 0.06 * sea_state          # a·k, slope of each component
    return WaveField(
        wavenumber=np.stack([np.cos(directions), np.sin(directions)], 1) * k[:, None],
        amplitude_m=steepness / k * rng.uniform(0.5, 1.0, NUM_WAVES),
        omega=np.sqrt(GRAVITY_M_S2 * k),
        phase=rng.uniform(0, 2 * math.pi, NUM_WAVES),
    )


def _wave_slopes(waves: WaveField, x: np.ndarray, y: np.ndarray,
                 time_s: float) -> tuple[np.ndarray, np.ndarray]:
    """∂η/∂x and ∂η/∂y of η = Σ a cos(k·(x, y) − ωt + φ) on the grid (x, y)."""
    slope_x = np.zeros_like(x)
    slope_y = np.zeros_like(x)
    for (kx, ky), a, w, p in zip(waves.wavenumber, waves.amplitude_m, waves.omega, waves.phase):
        s = -a * np.sin(kx * x + ky * y - w * time_s + p)
        slope_x += s * kx
        slope_y += s * ky
    return slope_x, slope_y
