"""Loss terms of the fit against hand-computed values."""

import pytest
import torch

from dolphinfit.core.fit import losses


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


def _axis(pitch_deg: float, heading_deg: float = 0.0) -> list[float]:
    pitch, heading = torch.deg2rad(torch.tensor([pitch_deg, heading_deg], dtype=torch.float64))
    return [float(torch.cos(pitch) * torch.cos(heading)),
            float(torch.cos(pitch) * torch.sin(heading)), float(torch.sin(pitch))]


def test_glide_prior_is_zero_along_the_axis_and_charges_a_level_tilted_animal():
    """An animal sinking along its axis (0.4 m forward and 0.4·tan 20° down per 0.5 s, at a
    heading of 30°) costs nothing; one pitched 30° nose down that stays level, moving 0.8 m
    per 0.4 s, is off by 0.8·tan 30° / 0.4 s = 1.155 m/s: (1.155)² (m/s)². A lone frame
    costs nothing."""
    time_s = torch.tensor([0.0, 0.5, 1.0], dtype=torch.float64)
    heading = torch.deg2rad(torch.tensor(30.0, dtype=torch.float64))
    forward = torch.tensor([_axis(-20.0, 30.0)] * 3, dtype=torch.float64)
    step = torch.stack([0.4 * torch.cos(heading), 0.4 * torch.sin(heading),
                        -0.4 * torch.tan(torch.deg2rad(torch.tensor(20.0, dtype=torch.float64)))])
    transl = torch.stack([k * step for k in range(3)])
    assert float(losses.glide_prior(transl, forward, time_s)) == pytest.approx(0.0, abs=1e-20)

    level = torch.tensor([[0.0, 0.0, -0.15], [0.8, 0.0, -0.15]], dtype=torch.float64,
                         requires_grad=True)
    tilted = torch.tensor([_axis(-30.0)] * 2, dtype=torch.float64)
    value = losses.glide_prior(level, tilted, torch.tensor([0.0, 0.4], dtype=torch.float64))
    assert value.detach().item() == pytest.approx((0.8 * 3 ** -0.5 / 0.4) ** 2)
    value.backward()
    assert level.grad[1, 2] > 0      # descent lowers the later root: it sinks as it points
    assert losses.glide_prior(level[:1], tilted[:1], time_s[:1]).detach().item() == 0.0


def test_pitch_bend_prior_charges_a_lasting_bend_not_a_stroke():
    """Two spine parts and a fin over four frames. A stroke that bends the tail ±0.1 rad
    about straight averages to nothing and costs nothing; a tail held 0.1 rad down in every
    frame costs 0.1² per part, 0.02 for two, as one frame does alone. Roll, lateral bend and
    the fin's rotations are free."""
    spine = torch.tensor([True, True, False])
    stroke = torch.zeros(4, 3, 3)
    stroke[:, :2, 1] = torch.tensor([0.1, -0.1, 0.1, -0.1])[:, None]
    stroke[:, :, 0], stroke[:, :, 2], stroke[:, 2, 1] = 0.3, -0.2, 0.5
    assert float(losses.pitch_bend_prior(stroke, spine)) == pytest.approx(0.0, abs=1e-12)

    held = stroke.clone()
    held[:, :2, 1] = -0.1
    held.requires_grad_(True)
    value = losses.pitch_bend_prior(held, spine)
    assert value.item() == pytest.approx(0.02)
    assert losses.pitch_bend_prior(held[:1], spine).item() == pytest.approx(0.02)
    value.backward()
    assert (held.grad[:, :2, 1] < 0).all()            # descent straightens the tail
    assert held.grad[:, :, [0, 2]].abs().max() == 0 and held.grad[:, 2].abs().max() == 0
