"""White water where an animal breaks the surface: splash at its waterline and a wake behind.

Each frame, foam is born just outside the parts that have come out of the water since the last
frame (the bow pushing through the surface, flukes breaking it), then spreads and decays over
about a second, so a swimming animal leaves a trail of it. Foam is bubbly (modulated by a fixed
fine texture) and lies over everything, but only faintly over the animals: the true mask stays
the body.
"""

import math

import cv2
import numpy as np

from dolphinfit.core.synth.compose import DolphinLayer
from dolphinfit.core.synth.config import SynthConfig

FOAM_RGB = np.array([0.86, 0.90, 0.90], dtype=np.float32)
FOAM_LIFETIME_S = 1.0
RING_M = 0.06           # foam is born this far outside the newly emerged outline
SPREAD_M_S = 0.08       # how fast foam spreads (blur σ growth)
EMERGED_DEPTH_M = 0.005
OVER_ANIMAL_ALPHA = 0.15


class Whitewater:
    """The foam of one clip, carried from frame to frame (image ≈ water plane: the camera
    hovers over the world origin)."""

    def __init__(self, config: SynthConfig, rng: np.random.Generator, gsd_m_per_px: float):
        self.config = config
        self.foam = np.zeros((config.height_px, config.width_px), dtype=np.float32)
        self.emerged = np.zeros((config.height_px, config.width_px), dtype=np.uint8)
        self.decay = math.exp(-1.0 / (config.fps * FOAM_LIFETIME_S))
        self.spread_px = SPREAD_M_S / config.fps / gsd_m_per_px
        ring_px = max(1, int(round(RING_M / gsd_m_per_px)))
        self.kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * ring_px + 1,) * 2)
        self.blob_px = 1.5 * ring_px          # soft clumps of foam, not lines
        fine = rng.random((config.height_px // 2, config.width_px // 2)).astype(np.float32)
        fine = cv2.resize(cv2.GaussianBlur(fine, (0, 0), 1.5),
                          (config.width_px, config.height_px), interpolation=cv2.INTER_LINEAR)
        self.bubbles = np.clip((fine - 0.4) * 8.0, 0.0, 1.0)

    def apply(self, frame: np.ndarray, layers: list[DolphinLayer | None]) -> np.ndarray:
        """Advance the foam one frame, born around the newly emerged parts of ``layers`` (the
        animals), and lay it over ``frame``."""
        self.foam *= self.decay
        if self.spread_px > 0.3:
            self.foam = cv2.GaussianBlur(self.foam, (0, 0), self.spread_px)
        emerged = np.zeros_like(self.emerged)
        body = np.zeros(self.foam.shape, dtype=np.float32)
        for layer in layers:
            if layer is not None:
                h, w = layer.alpha.shape
                window = (slice(layer.y0, layer.y0 + h), slice(layer.x0, layer.x0 + w))
                emerged[window] |= (layer.alpha >= 0.5) & (layer.depth_m < EMERGED_DEPTH_M)
                np.maximum(body[window], layer.alpha, out=body[window])
        born = cv2.dilate(emerged & (1 - self.emerged), self.kernel) & (body < 0.5)
        self.foam += self.config.splash * cv2.GaussianBlur(born.astype(np.float32), (0, 0),
                                                           self.blob_px)
        self.emerged = emerged
        alpha = np.minimum(np.clip(self.foam, 0.0, 1.0) * self.bubbles,
                           1.0 - (1.0 - OVER_ANIMAL_ALPHA) * body)
        return frame * (1.0 - alpha[..., None]) + FOAM_RGB * alpha[..., None]
