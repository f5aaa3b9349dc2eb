"""Soft targets that DIB-R's soft silhouette can match without shrinking the animal.

The rendered soft mask is 1 on covered pixels and decays outside over a few pixels. Against a
hard target mask its IoU optimum therefore shrinks the model (about −4 % in scale at 1.46 cm
per pixel; see tests/core/render/test_inverse_rendering.py). We compare like with like: the
target is given the renderer's own edge profile, A_target(p) = f(d(p)) outside the mask, with
d the distance to the nearest mask pixel and f measured on a render of the model itself as the
mean soft value of uncovered pixels at each distance from the coverage.
"""

import cv2
import numpy as np
import torch

PROFILE_BIN_PX = 0.25
PROFILE_MAX_PX = 8.0


def outside_distance_px(masks: np.ndarray) -> np.ndarray:
    """(T, H, W) float32 distance of each pixel to the nearest mask pixel (0 inside)."""
    return np.stack([cv2.distanceTransform((~mask).astype(np.uint8), cv2.DIST_L2,
                                           cv2.DIST_MASK_PRECISE) for mask in masks])


def edge_profile(soft_mask: torch.Tensor, coverage: torch.Tensor) -> np.ndarray:
    """(B,) mean soft value of uncovered pixels per distance bin from the coverage.

    soft_mask, coverage: (T, H, W). Bin k covers distances [k·0.25, (k + 1)·0.25) px; empty
    bins take the value of the bin before them (0 beyond the last populated one).
    """
    covered = coverage.cpu().numpy()
    distance = outside_distance_px(covered)
    soft = soft_mask.detach().cpu().numpy()
    outside = ~covered
    bins = np.minimum((distance[outside] / PROFILE_BIN_PX).astype(int),
                      int(PROFILE_MAX_PX / PROFILE_BIN_PX))
    sums = np.bincount(bins, weights=soft[outside], minlength=int(PROFILE_MAX_PX / PROFILE_BIN_PX) + 1)
    counts = np.bincount(bins, minlength=len(sums))
    profile = np.zeros(len(sums))
    last = 0.0
    for k in range(len(sums)):
        last = sums[k] / counts[k] if counts[k] else (last if k < 3 else 0.0)
        profile[k] = last
    profile[-1] = 0.0
    return profile


def soft_targets(masks: torch.Tensor, profile: np.ndarray, edge_scale: float) -> torch.Tensor:
    """(T, H, W) targets: 1 on the mask, ``edge_scale`` × the edge profile outside it."""
    hard = masks.cpu().numpy() > 0.5
    distance = outside_distance_px(hard)
    bins = np.minimum((distance / PROFILE_BIN_PX).astype(int), len(profile) - 1)
    soft = np.where(hard, 1.0, edge_scale * profile[bins])
    return torch.as_tensor(soft, dtype=masks.dtype, device=masks.device)
