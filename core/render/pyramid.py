"""Blurred, downsampled silhouettes for a wide basin of attraction early in a fit.

With no overlap between rendered and target masks the IoU gradient is exactly zero
(reference/rendering.md §8). Average-pooling by 8, 4 and 2 and blurring each level with a
Gaussian (σ = 4, 4 and 2 px) spreads every silhouette over tens of pixels, so an L2 between the
pyramids pulls a distant render towards its target.

Pooling (a last, partial window averages the pixels it holds) and blurring (zero padding,
radius 3σ) are both separable linear maps, so a level is A_rows · X · A_colsᵀ with two small
matrices per image size: two matrix products, forward and backward, where convolutions with
one channel were 3× slower on the CPU.
"""

import math
from functools import lru_cache

import torch

PYRAMID_LEVELS: tuple[tuple[int, float], ...] = ((8, 4.0), (4, 4.0), (2, 2.0))


def gaussian_kernel(sigma_px: float, dtype: torch.dtype) -> torch.Tensor:
    """(2r + 1,) normalised Gaussian taps, r = max(1, round(3σ))."""
    radius = max(1, int(round(3.0 * sigma_px)))
    offsets = torch.arange(-radius, radius + 1, dtype=dtype)
    kernel = torch.exp(-0.5 * (offsets / sigma_px) ** 2)
    return kernel / kernel.sum()


@lru_cache(maxsize=64)
def pool_blur_matrix(size: int, factor: int, sigma_px: float, dtype: torch.dtype,
                     device: torch.device) -> torch.Tensor:
    """(⌈size / factor⌉, size) matrix of average pooling by ``factor`` along one axis, then
    a Gaussian blur of σ ``sigma_px`` with zero padding; built on the CPU (a loop of small
    writes), kept on ``device``."""
    pooled = math.ceil(size / factor)
    pool = torch.zeros(pooled, size, dtype=dtype)
    for row in range(pooled):
        start, stop = row * factor, min(size, (row + 1) * factor)
        pool[row, start:stop] = 1.0 / (stop - start)
    kernel = gaussian_kernel(sigma_px, dtype)
    radius = (len(kernel) - 1) // 2
    blur = torch.zeros(pooled, pooled, dtype=dtype)
    for offset, tap in zip(range(-radius, radius + 1), kernel.tolist()):
        if abs(offset) < pooled:
            blur += tap * torch.diag(torch.ones(pooled - abs(offset), dtype=dtype), offset)
    return (blur @ pool).to(device)


def silhouette_pyramid(masks: torch.Tensor) -> list[torch.Tensor]:
    """Blurred pooled copies of soft masks (T, H, W), coarsest first."""
    height, width = masks.shape[1:]
    return [pool_blur_matrix(height, factor, sigma, masks.dtype, masks.device) @ masks
            @ pool_blur_matrix(width, factor, sigma, masks.dtype, masks.device).T
            for factor, sigma in PYRAMID_LEVELS]


def pyramid_loss(rendered: torch.Tensor, target: list[torch.Tensor]) -> torch.Tensor:
    """Sum over levels of the mean squared difference between the pyramid of ``rendered``
    and ``target``, a ``silhouette_pyramid`` (computed once: the targets do not change)."""
    return sum(((a - b) ** 2).mean() for a, b in zip(silhouette_pyramid(rendered), target))
