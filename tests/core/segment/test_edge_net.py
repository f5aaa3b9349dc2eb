"""The edge network: its input, its weights file, its training recipe, and the bundled weights
on a clip none of its training clips was drawn like."""

from dataclasses import replace

import numpy as np
import pytest
import torch

from dolphinfit.core.bench.suites import SUITE
from dolphinfit.core.errors import InputError
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.segment.edge_data import (
    FIRST_SEED, Window, clip_windows, load_windows, save_windows, training_configs,
)
from dolphinfit.core.segment.edge_net import (
    MAX_SIDE_PX, WEIGHTS_PATH, EdgeNet, EdgeWeights, LearnedEdges, load_weights, net_input,
    _reach, padded_to_multiple, save_weights,
)
from dolphinfit.core.segment.edge_training import (
    PRIOR_CUT_KEEP, TrainSettings, cut_prior, loss_of, train, training_patch,
)
from dolphinfit.core.segment.edge_steps import ColourEdges, make_edge_step
from dolphinfit.core.segment.net_settings import NetSettings
from dolphinfit.core.segment.salient import SalientNet
from dolphinfit.core.synth.clip import make_clip
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.water import with_water


def _ellipse_window(side: int = 120, half_length: float = 0.35,
                    half_width: float = 0.07) -> Window:
    """Green water with a grey ellipse (half axes × ``side``); the prior one pixel too small
    all round."""
    rows, cols = np.mgrid[:side, :side]
    body = (((cols - side / 2) / (half_length * side)) ** 2
            + ((rows - side / 2) / (half_width * side)) ** 2)
    target = body <= 1.0
    crop = np.zeros((side, side, 3), np.uint8)
    crop[:] = (40, 110, 90)
    crop[target] = (170, 170, 165)
    prior = body <= 0.8
    return Window(crop, (target * 230).astype(np.uint8), prior, target)


def test_the_input_centres_the_water_and_carries_saliency_and_prior():
    window = _ellipse_window()
    x = net_input(window.crop_rgb, window.saliency / 255.0, window.prior)
    assert x.shape == (5, 120, 120) and x.dtype == np.float32
    water = ~window.target
    assert np.abs(x[:3, water]).max() == 0.0          # the median colour is the water's
    assert (x[:3, window.target].mean(axis=1) > 1.0).all()   # the animal lies spreads away
    assert np.allclose(x[3], window.saliency / 255.0)
    assert np.array_equal(x[4] == 1.0, window.prior)


def test_inputs_are_padded_to_the_networks_multiple():
    x = torch.zeros(1, 5, 101, 96)
    assert padded_to_multiple(x).shape == (1, 5, 104, 96)


def test_weights_read_back_give_the_same_outlines(tmp_path):
    torch.manual_seed(0)
    net = EdgeNet().eval()
    with torch.no_grad():   # give the batch norms' running statistics non-default values
        for module in net.modules():
            if isinstance(module, torch.nn.BatchNorm2d):
                module.running_mean.uniform_(-0.1, 0.1)
                module.running_var.uniform_(0.5, 1.5)
    path = tmp_path / "edges.npz"
    save_weights(net, {"channels": [8, 16, 32, 48], "note": "test"}, path)
    loaded = load_weights(path)
    assert loaded.meta["note"] == "test"
    window = _ellipse_window()
    ours = LearnedEdges(EdgeWeights(net, {})).probability(
        window.crop_rgb, window.saliency / 255.0, window.prior)
    theirs = LearnedEdges(loaded).probability(window.crop_rgb, window.saliency / 255.0,
                                              window.prior)
    assert np.array_equal(ours, theirs)


def test_missing_or_unreadable_weights_name_the_file(tmp_path):
    with pytest.raises(InputError, match="missing.npz: not found"):
        load_weights(tmp_path / "missing.npz")
    broken = tmp_path / "broken.npz"
    broken.write_bytes(b"not weights")
    with pytest.raises(InputError, match="broken.npz: unreadable"):
        load_weights(broken)
    cut = tmp_path / "cut.npz"      # a copy broken off half way
    cut.write_bytes(WEIGHTS_PATH.read_bytes()[:20_000])
    with pytest.raises(InputError, match="cut.npz: unreadable"):
        load_weights(cut)


def _silent_net() -> EdgeWeights:
    """A network that calls no pixel the animal."""
    net = EdgeNet().eval()
    with torch.no_grad():
        net.head.weight.zero_()
        net.head.bias.fill_(-30.0)
    return EdgeWeights(net, {})


def test_the_outline_step_keeps_its_mask_when_it_has_nothing_better():
    """An empty mask stays empty; where the network's outline does not touch the chosen
    component, the component is kept rather than the frame lost."""
    window = _ellipse_window()
    saliency = window.saliency / 255.0
    edges = LearnedEdges(_silent_net())
    assert not edges(window.crop_rgb, saliency, np.zeros_like(window.prior)).any()
    assert np.array_equal(edges(window.crop_rgb, saliency, window.prior), window.prior)


def test_small_windows_of_odd_sides_are_answered_at_their_own_size():
    """The tracker's smallest windows (48 px) around a small animal, cut to odd sides."""
    window = _ellipse_window(51)
    edges = LearnedEdges()
    for rows, cols in ((slice(10, 47), slice(1, 50)), (slice(0, 51), slice(3, 48))):
        crop = np.ascontiguousarray(window.crop_rgb[rows, cols])
        prior, target = window.prior[rows, cols], window.target[rows, cols]
        out = edges(crop, window.saliency[rows, cols] / 255.0, prior)
        assert out.shape == prior.shape and out.dtype == bool
        assert mask_iou(out, target) >= mask_iou(prior, target) - 0.05


def test_an_unknown_outline_step_is_refused():
    with pytest.raises(InputError, match="network tracker edges: one of network, colour"):
        make_edge_step(NetSettings(edges="grabcut"))


def test_a_large_window_is_looked_at_downscaled_and_answered_at_full_size():
    """The tracker's window is twice the animal's length and a dolphin about a sixth as wide
    as long, so a window shrunk to ``MAX_SIDE_PX`` shows a body at most 0.08 of it wide."""
    window = _ellipse_window(2 * MAX_SIDE_PX, half_length=0.25, half_width=0.04)
    edges = LearnedEdges()
    probability = edges.probability(window.crop_rgb, window.saliency / 255.0, window.prior)
    assert probability.shape == window.prior.shape
    assert mask_iou(probability >= 0.5, window.target) > 0.95


def test_the_network_run_around_the_prior_outlines_as_over_the_whole_window():
    """Run only on the prior's box grown by ``REACH_PX`` (here a third of the window), the
    bundled network gives the outline it gives over the whole window, to the pixel."""
    window = _ellipse_window(400, half_length=0.25, half_width=0.04)
    edges = LearnedEdges()
    x = torch.from_numpy(net_input(window.crop_rgb, window.saliency / 255.0, window.prior))
    with torch.inference_mode():
        whole = edges.weights.net(padded_to_multiple(x[None]))[0, 0, :400, :400].numpy() >= 0.0
    around = edges.probability(window.crop_rgb, window.saliency / 255.0, window.prior) >= 0.5
    rows, cols = _reach(window.prior)
    assert (rows.stop - rows.start) * (cols.stop - cols.start) < 0.4 * 400 ** 2
    assert whole.any() and np.array_equal(around, whole)


def test_training_clips_are_drawn_widely_and_never_as_the_suite():
    configs = training_configs(40, seed=0)
    assert configs == training_configs(40, seed=0)
    assert {c.seed for c in configs}.isdisjoint({s.config.seed for s in SUITE})
    assert min(c.seed for c in configs) >= FIRST_SEED
    assert {c.colouration for c in configs} == {"dark", "light_grey"}
    assert len({c.water_rgb for c in configs}) == 40   # jittered around the presets
    assert any(c.companion_offset_m is not None and abs(c.companion_offset_m) < 0.8
               for c in configs)                   # touching pairs
    assert any(c.glitter > 0.5 for c in configs) and any(c.splash > 0.5 for c in configs)


def test_patches_move_the_input_and_the_target_together():
    """However a patch is scaled, turned, mirrored and coloured, its prior channel lies on
    its target."""
    window = _ellipse_window()
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(20):
        x, target, valid = training_patch(window, 64, 1.0, rng)
        assert x.shape == (5, 64, 64) and target.shape == valid.shape == (64, 64)
        prior = x[4] > 0.5
        if prior.sum() > 20:
            assert (prior & (target > 0.5)).sum() > 0.6 * prior.sum()
            checked += 1
    assert checked >= 10


def test_patches_beyond_a_small_window_are_padding_and_not_scored():
    window = _ellipse_window(100)
    x, target, valid = training_patch(window, 160, 1.0, np.random.default_rng(0))
    assert 0 < valid.sum() < 160 * 160
    assert not target[valid == 0].any() and not x[:, valid == 0].any()
    logits = torch.full((1, 160, 160), 30.0)
    loss_all_animal = loss_of(logits, torch.from_numpy(target)[None],
                              torch.from_numpy(valid)[None], 0.0)
    assert float(loss_all_animal) == pytest.approx(
        30.0 * (1 - target.sum() / valid.sum()), rel=1e-3)


def test_a_cut_prior_keeps_one_end_of_the_animal():
    """Cut across its long axis (here the columns), keeping 45–85 % of its length from one
    end."""
    prior = _ellipse_window(200).prior
    cols = np.nonzero(prior.any(axis=0))[0]
    length = cols.max() - cols.min()
    ends = set()
    for seed in range(12):
        cut = cut_prior(prior, np.random.default_rng(seed))
        assert not (cut & ~prior).any()
        kept = np.nonzero(cut.any(axis=0))[0]
        assert PRIOR_CUT_KEEP[0] - 0.02 <= (kept.max() - kept.min()) / length \
            <= PRIOR_CUT_KEEP[1] + 0.02
        assert np.array_equal(cut[:, kept.min():kept.max() + 1],
                              prior[:, kept.min():kept.max() + 1])
        ends.add(kept.min() == cols.min())
    assert ends == {True, False}


def test_training_fits_a_window_it_is_shown():
    """Eighty steps on one window lift its outline from the too-small prior (IoU 0.80, its
    outline 1.2 px inside the truth's) to the truth (0.97–1.00 over training seeds 0–4; its
    outline 0.15 px out at seed 0)."""
    window = _ellipse_window()
    settings = replace(TrainSettings(), steps=80, batch=4, patch_px=64,
                       learning_rate=5e-3, final_learning_rate=1e-3)
    net, record = train([window], [window], settings, log=lambda line: None)
    assert record["checks"][-1]["prior_iou"] == pytest.approx(0.802, abs=0.001)
    assert record["checks"][-1]["held_out_iou"] > 0.95
    assert abs(record["checks"][-1]["held_out_offset_px"]) < 0.25
    assert record["checks"][-1]["held_out_abs_offset_px"] < 0.25


def test_windows_read_back_as_written(tmp_path):
    windows = [_ellipse_window(60), _ellipse_window(80)]
    save_windows(windows, tmp_path / "w.npz")
    back = load_windows(tmp_path / "w.npz")
    assert len(back) == 2
    for one, other in zip(windows, back, strict=True):
        for name in ("crop_rgb", "saliency", "prior", "target"):
            assert np.array_equal(getattr(one, name), getattr(other, name))


@pytest.fixture(scope="module")
def held_out_windows(tmp_path_factory) -> list[Window]:
    """Windows of a light-grey animal over green water with glitter and a companion, at the
    suite's pixel size (960 px wide from 10 m is 1920 px from 20 m), drawn with a seed and
    settings no training clip has."""
    config = with_water(SynthConfig(
        seed=9_999, width_px=960, height_px=540, fps=2.0, duration_s=2.0, altitude_m=10.0,
        length_m=2.4, colouration="light_grey", glitter=0.4, wet_specular=0.3,
        companion_offset_m=1.2, heading_deg=35.0, dive_depth_m=0.3), "green")
    files = make_clip(config, tmp_path_factory.mktemp("held_out"))
    return clip_windows(files, seed=1, net=SalientNet())


def test_the_bundled_network_outlines_unseen_windows_better_than_colour(held_out_windows):
    """On windows of a clip unlike any it was trained on, the bundled network's outline is
    closer to the truth than the tracker's component and than the colour edges (measured:
    see the README's masks table for the suite)."""
    assert len(held_out_windows) >= 3
    learned, colour, prior = [], [], []
    edges, by_colour = LearnedEdges(), ColourEdges(NetSettings())
    for window in held_out_windows:
        saliency = window.saliency / 255.0
        learned.append(mask_iou(edges(window.crop_rgb, saliency, window.prior), window.target))
        colour.append(mask_iou(by_colour(window.crop_rgb, saliency, window.prior),
                               window.target))
        prior.append(mask_iou(window.prior, window.target))
    assert np.mean(learned) > max(np.mean(colour), np.mean(prior)) + 0.02
    assert np.mean(learned) >= 0.9


def test_named_the_cpu_the_network_and_its_training_are_the_same_to_the_last_bit():
    """The outline step, and a few training steps, asked for on the CPU by name (core.device)
    give what they give without a device."""
    window = _ellipse_window()
    saliency = window.saliency / 255.0
    np.testing.assert_array_equal(
        LearnedEdges(device=torch.device("cpu")).probability(window.crop_rgb, saliency,
                                                             window.prior),
        LearnedEdges().probability(window.crop_rgb, saliency, window.prior))
    settings = replace(TrainSettings(), steps=3, batch=2, patch_px=64)
    nets = [train([window], [window], settings, log=lambda line: None, **where)[0]
            for where in ({}, {"device": torch.device("cpu")})]
    for (name, ours), theirs in zip(nets[1].state_dict().items(),
                                    nets[0].state_dict().values(), strict=True):
        assert torch.equal(ours, theirs), name


@pytest.mark.skipif(not torch.cuda.is_available(), reason="no CUDA GPU")
def test_on_a_cuda_gpu_the_network_outlines_as_on_the_cpu_and_trains(tmp_path):
    """On the GPU the probabilities lie within 0.05 of the CPU's (its convolutions may run
    in TF32) and the outlines agree (IoU > 0.99); a few training steps run there and the
    weights are written from it and read back."""
    window = _ellipse_window()
    saliency = window.saliency / 255.0
    cpu = LearnedEdges().probability(window.crop_rgb, saliency, window.prior)
    gpu = LearnedEdges(device=torch.device("cuda")).probability(window.crop_rgb, saliency,
                                                               window.prior)
    assert gpu.dtype == cpu.dtype and gpu.shape == cpu.shape
    np.testing.assert_allclose(gpu, cpu, atol=0.05)
    assert mask_iou(gpu >= 0.5, cpu >= 0.5) > 0.99
    settings = replace(TrainSettings(), steps=3, batch=2, patch_px=64)
    net, record = train([window], [window], settings, log=lambda line: None,
                        device=torch.device("cuda"))
    assert next(net.parameters()).is_cuda and np.isfinite(record["checks"][-1]["loss"])
    save_weights(net, record, tmp_path / "edges.npz")
    assert load_weights(tmp_path / "edges.npz").meta["settings"]["steps"] == 3
