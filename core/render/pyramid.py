"""Blurred, downsampled silhouettes for a wide basin of attraction early in a fit.

With no overlap between rendered and target masks the IoU gradient is exactly zero
(reference/rendering.md §8). Average-pooling by 8, 4 and 2 and blurring each level with a
Gaussian (σ = 4, 4 and 2 px) spreads every silhouette over tens of pixels, so an L2 between the
pyramids pulls a distant render towards its target.
"""

import torch
import torch.nn.functional as F

PYRAMID_LEVELS: tuple[tuple[int, float], ...] = ((8, 4.0), (4, 4.0), (2, 2.0))


def gaussian_blur(images: torch.Tensor, sigma_px: float) -> torch.Tensor:
    """(T, H, W) images blurred by a separable Gaussian (zero padding, radius 3σ)."""
    radius = max(1, int(round(3.0 * sigma_px)))
    offsets = torch.arange(-radius, radius + 1, dtype=images.dtype)
    kernel = torch.exp(-0.5 * (offsets / sigma_px) ** 2)
    kernel = kernel / kernel.sum()
    batch = images[:, None]
    batch = F.conv2d(batch, kernel.reshape(1, 1, 1, -1), padding=(0, radius))
    batch = F.conv2d(batch, kernel.reshape(1, 1, -1, 1), padding=(radius, 0))
    return batch[:, 0]


def silhouette_pyramid(masks: torch.Tensor) -> list[torch.Tensor]:
    """Blurred pooled copies of soft masks (T, H, W), coarsest first."""
    return [gaussian_blur(F.avg_pool2d(masks[:, None], factor, ceil_mode=True)[:, 0], sigma)
            for factor, sigma in PYRAMID_LEVELS]


def pyramid_loss(rendered: torch.Tensor, target: list[torch.Tensor]) -> torch.Tensor:
    """Sum over levels of the mean squared difference between the pyramid of ``rendered``
    and ``target``, a ``silhouette_pyramid`` (computed once: the targets do not change)."""
    return sum(((a - b) ** 2).mean() for a, b in zip(silhouette_pyramid(rendered), target))
