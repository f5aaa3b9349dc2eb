"""Colour models of the animal and the water in CIE Lab, and the per-pixel tests on them.

Lab values use OpenCV's 8-bit scaling (L, a, b each in 0…255). A model is a Gaussian: mean
(3,) and covariance (3, 3). The animal-versus-water decision projects each pixel onto Fisher's
discriminant direction and reads the position between the two means as a coverage fraction
(0 = water, 1 = animal): a pixel on the outline is a blend of the two colours, so the 0.5
level of this fraction is where the animal covers half the pixel.
"""

from dataclasses import dataclass

import cv2
import numpy as np

MIN_VARIANCE = 4.0  # (grey levels)²: keeps covariances invertible on flat synthetic colours


def to_lab(frame_rgb: np.ndarray) -> np.ndarray:
    """(H, W, 3) float32 Lab of an (H, W, 3) uint8 RGB frame."""
    return cv2.cvtColor(frame_rgb, cv2.COLOR_RGB2LAB).astype(np.float32)


@dataclass(frozen=True, eq=False)
class ColourModel:
    """A Gaussian colour model in Lab: mean (3,) and covariance (3, 3), float64."""

    mean: np.ndarray
    cov: np.ndarray

    @classmethod
    def fit(cls, pixels: np.ndarray) -> "ColourModel":
        """The model of (N, 3) Lab pixels (N ≥ 1)."""
        pixels = np.asarray(pixels, dtype=np.float64).reshape(-1, 3)
        cov = np.cov(pixels, rowvar=False) if len(pixels) > 1 else np.zeros((3, 3))
        return cls(pixels.mean(axis=0), cov + MIN_VARIANCE * np.eye(3))

    def blend(self, other: "ColourModel", rate: float) -> "ColourModel":
        """A running update: (1 − rate) × this + rate × other."""
        return ColourModel((1 - rate) * self.mean + rate * other.mean,
                           (1 - rate) * self.cov + rate * other.cov)

    def distance(self, lab: np.ndarray) -> np.ndarray:
        """Mahalanobis distance of (..., 3) Lab pixels from this model: (...)."""
        delta = lab.reshape(-1, 3) - self.mean
        # sum over the colour axis of (delta · Σ⁻¹) · delta: the product first is a BLAS call,
        # and the whole twice as fast as one three-operand einsum (0.30 → 0.14 s on a 4K frame)
        squared = np.einsum("ni,ni->n", delta @ np.linalg.inv(self.cov), delta)
        return np.sqrt(squared).reshape(lab.shape[:-1]).astype(np.float32)


def _fisher_direction(animal: ColourModel, water: ColourModel) -> np.ndarray:
    """Fisher's discriminant direction (3,): pooled covariance⁻¹ × mean difference."""
    return np.linalg.solve(animal.cov + water.cov, animal.mean - water.mean)


def separation(animal: ColourModel, water: ColourModel) -> float:
    """How far apart the two means are along Fisher's direction, in pooled SDs."""
    direction = _fisher_direction(animal, water)
    delta = animal.mean - water.mean
    spread = np.sqrt(direction @ ((animal.cov + water.cov) / 2) @ direction)
    return float(direction @ delta / spread)


def coverage(lab: np.ndarray, animal: ColourModel, water: ColourModel) -> np.ndarray:
    """(H, W) float32 estimated animal coverage: 0 at the water mean, 1 at the animal mean."""
    direction = _fisher_direction(animal, water)
    scale = direction @ (animal.mean - water.mean)
    return (((lab - water.mean.astype(np.float32)) @ direction.astype(np.float32))
            / np.float32(scale))
