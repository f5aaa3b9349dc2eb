"""core.iou: one IoU for the fit (torch, batched) and the segmenters (numpy, per frame)."""

import numpy as np
import torch

from dolphinfit.core.iou import mask_iou


def test_iou_is_the_same_for_numpy_and_torch_and_one_for_two_empty_masks():
    """A 2×4 and a 2×7 block overlapping in 4 pixels: 4/18; two empty masks agree (1); one
    empty mask against a dolphin misses it (0). Batched over frames in torch as in numpy."""
    a, b = np.zeros((2, 4, 7), bool), np.zeros((2, 4, 7), bool)
    a[0, 1:3, 1:5] = True
    b[0, 2:4, :] = True
    expected = [4 / 18, 1.0]
    np.testing.assert_allclose(mask_iou(a, b), expected, rtol=1e-15)
    np.testing.assert_allclose(mask_iou(torch.from_numpy(a), torch.from_numpy(b)).numpy(),
                               expected, rtol=1e-7)
    assert mask_iou(a[0], b[0] & False) == 0.0 and mask_iou(a[1], b[1]) == 1.0
