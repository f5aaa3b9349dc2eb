"""A procedural sea seen from above: water colour, waves, sky reflection and sun glints.

The surface is a sum of directional deep-water waves (ω² = g·k) whose height η(x, y, t) and
slopes are evaluated in world metres on the water plane, at half the image resolution and
upsampled. Facets tilted towards the sun look brighter; glints appear where a facet mirrors the
sun into the camera (a sharp lobe about the half vector).

Optional: a seabed (``seabed_depth_m``), seen through the water as bed·E·T + water·(1 − T)
with T = exp(−k·depth) and E the caustic focusing of sunlight by the waves, E ≈ 1/|1 − d·∇²η|
with d = depth·(1 − 1/n), and refracted by the surface slopes like the submerged dolphin; and
glitter (``glitter``): one-frame sparkles of capillary facets, dense where the Cox–Munk slope
distribution lets a facet mirror the sun into the camera.
"""

import math
from dataclasses import dataclass

import cv2
import numpy as np

from dolphinfit.core.camera import N_WATER
from dolphinfit.core.synth.config import SynthConfig

GRAVITY_M_S2 = 9.81
NUM_WAVES = 10
SKY_RGB = np.array([0.55, 0.65, 0.78])
SKY_REFLECTANCE = 0.025      # Fresnel reflectance of water near normal incidence
GLINT_SHARPNESS = 900.0      # exp(κ(n·h − 1)) lobe of the glints
COLOUR_VARIATION = 0.06      # relative low-frequency patchiness of the water colour
SEAGRASS_RGB = np.array([0.17, 0.19, 0.11], dtype=np.float32)
CAUSTIC_RANGE = (0.8, 1.35)   # clip of the caustic focusing factor E
CAUSTIC_BLUR_PX = 2.5        # the sun's disc and the bed's roughness soften the caustics
GLITTER_SPARKLES_PER_MPX = 2500.0   # sparkles per megapixel at glitter = 1 over the glitter
GLITTER_FACET_LOBE = 60.0    # sparkles cluster on wave faces tilted towards the half vector
GLITTER_HAZE = 0.10          # diffuse brightening of the glitter pattern at glitter = 1


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
    glitter: np.ndarray | None = None   # (H, W) float32 sparkles, added on top; None if off


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
        self.extra_rng = np.random.default_rng([config.seed, 2])   # keeps the stream above
        self.bed = (None if config.seabed_depth_m is None
                    else _seabed(config, self.extra_rng))

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
        slope = cv2.resize(np.stack([slope_x, slope_y], -1).astype(np.float32), size,
                           interpolation=cv2.INTER_LINEAR)
        colour = self.colour
        if self.bed is not None:
            curvature = _wave_laplacian(self.waves, x, y, time_s)
            colour = self._through_water(
                cv2.resize(curvature.astype(np.float32), size, interpolation=cv2.INTER_LINEAR),
                slope, altitude_m / focal_px)
        rgb = colour * lit[..., None] + SKY_REFLECTANCE * SKY_RGB.astype(np.float32)
        return SeaFrame(
            rgb=rgb,
            glints=cv2.resize(glint.astype(np.float32), size, interpolation=cv2.INTER_LINEAR),
            slope=slope,
            glitter=(self._glitter(halfway, (normal * halfway).sum(-1), size)
                     if cfg.glitter > 0 else None),
        )

    def _through_water(self, laplacian: np.ndarray, slope: np.ndarray,
                       gsd_m_per_px: float) -> np.ndarray:
        """(H, W, 3) water colour with the seabed seen through it (module doc)."""
        depth = self.config.seabed_depth_m
        bend = depth * (1.0 - 1.0 / N_WATER)
        focus = cv2.GaussianBlur(np.clip(1.0 / np.maximum(np.abs(1.0 - bend * laplacian), 1e-6),
                                         *CAUSTIC_RANGE),
                                 (0, 0), CAUSTIC_BLUR_PX)
        h, w = laplacian.shape
        cols, rows = np.meshgrid(np.arange(w, dtype=np.float32), np.arange(h, dtype=np.float32))
        shift = bend * slope / gsd_m_per_px
        bed = cv2.remap(self.bed, cols - shift[..., 0], rows + shift[..., 1], cv2.INTER_LINEAR,
                        borderMode=cv2.BORDER_REFLECT)
        transmit = np.exp(-depth * np.asarray(self.config.clarity_per_m, dtype=np.float32))
        water = np.asarray(self.config.water_rgb, dtype=np.float32)
        return bed * focus[..., None] * transmit + water * (1.0 - transmit)

    def _glitter(self, halfway: np.ndarray, facing: np.ndarray,
                 size: tuple[int, int]) -> np.ndarray:
        """(H, W) one frame of sparkles; ``halfway`` (h, w, 3) the half vectors and
        ``facing`` (h, w) the waves' normal · half vector, at half size."""
        cfg = self.config
        wind_m_s = 2.0 + 10.0 * cfg.sea_state
        slope_variance = 0.003 + 0.00512 * wind_m_s          # Cox & Munk (1954)
        tan2 = (halfway[..., 0] ** 2 + halfway[..., 1] ** 2) / halfway[..., 2] ** 2
        envelope = np.exp(-tan2 / slope_variance).astype(np.float32)
        width, height = size
        count = int(cfg.glitter * GLITTER_SPARKLES_PER_MPX * width * height / 1e6
                    * float(envelope.mean()) / max(float(envelope.max()), 1e-6))
        sparkles = np.zeros((height, width), dtype=np.float32)
        if count > 0:
            density = envelope * np.exp(GLITTER_FACET_LOBE * (facing - 1.0))
            weights = density.ravel() / density.sum()
            cells = self.extra_rng.choice(envelope.size, size=count, p=weights)
            rows = 2 * (cells // envelope.shape[1]) + self.extra_rng.integers(0, 2, count)
            cols = 2 * (cells % envelope.shape[1]) + self.extra_rng.integers(0, 2, count)
            np.add.at(sparkles, (rows, cols),
                      self.extra_rng.lognormal(math.log(3.0), 0.7, count).astype(np.float32))
            sparkles = cv2.GaussianBlur(sparkles, (0, 0), 0.7)
        haze = cv2.resize(envelope, size, interpolation=cv2.INTER_LINEAR)
        return sparkles + cfg.glitter * GLITTER_HAZE * haze


def _seabed(config: SynthConfig, rng: np.random.Generator) -> np.ndarray:
    """(H, W, 3) float32 albedo of a sand bed with dark seagrass patches and sand ripples."""
    height, width = config.height_px, config.width_px

    def noise(cell_px: float) -> np.ndarray:
        coarse = rng.normal(0.0, 1.0, (int(height / cell_px) + 2, int(width / cell_px) + 2))
        return cv2.resize(coarse.astype(np.float32), (width, height),
                          interpolation=cv2.INTER_CUBIC)

    patches = noise(160.0) + 0.5 * noise(40.0)
    threshold = np.quantile(patches, 1.0 - config.seabed_cover) if config.seabed_cover else np.inf
    grass = np.clip((patches - threshold) / 0.6 + 0.5, 0.0, 1.0)[..., None]
    angle = rng.uniform(0, math.pi)
    cols, rows = np.meshgrid(np.arange(width, dtype=np.float32),
                             np.arange(height, dtype=np.float32))
    ripples = np.sin(0.35 * (cols * math.cos(angle) + rows * math.sin(angle)) + 3.0 * noise(30.0))
    sand = (np.asarray(config.seabed_rgb, dtype=np.float32)
            * (1.0 + 0.08 * noise(12.0) + 0.04 * ripples + 0.03 * noise(2.0))[..., None])
    seagrass = SEAGRASS_RGB * (1.0 + 0.25 * noise(4.0))[..., None]
    return (sand * (1.0 - grass) + seagrass * grass).astype(np.float32)


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


def _wave_laplacian(waves: WaveField, x: np.ndarray, y: np.ndarray,
                    time_s: float) -> np.ndarray:
    """∇²η of η = Σ a cos(k·(x, y) − ωt + φ) on the grid (x, y)."""
    laplacian = np.zeros_like(x)
    for (kx, ky), a, w, p in zip(waves.wavenumber, waves.amplitude_m, waves.omega, waves.phase):
        laplacian -= a * (kx * kx + ky * ky) * np.cos(kx * x + ky * y - w * time_s + p)
    return laplacian


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
