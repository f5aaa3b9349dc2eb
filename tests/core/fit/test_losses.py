"""Loss terms of the fit against hand-computed values."""

import pytest
import torch

from core.fit import losses


def test_depth_prior_is_the_mean_squared_depth_deviation():
    """Roots 0.25 m and 0.05 m down against 0.15 m: both 0.1 m off, so 0.01 m²; zero at the
    prior's depth; the gradient pulls each root back towards it."""
    transl = torch.tensor([[0.3, 0.1, -0.25], [0.5, 0.2, -0.05]], requires_grad=True)
    value = losses.depth_prior(transl, 0.15)
    assert value.item() == pytest.approx(0.01)
    value.backward()
    assert transl.grad[:, :2].abs().max() == 0
    # descent raises the deep one and lowers the shallow one
    assert transl.grad[0, 2] < 0 < transl.grad[1, 2]
    assert float(losses.depth_prior(torch.tensor([[0.0, 0.0, -0.15]]), 0.15)) == 0.0
