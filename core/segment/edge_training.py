"""Training the edge network (``edge_net``) on windows of random synthetic clips.

``dolphinfit train edges`` runs it: ``make_windows`` renders the clips of
``edge_data.training_configs`` into the cache and cuts their windows (in worker processes);
``train`` fits the network on patches of them, and ``save_weights`` writes the result with
what it was trained on. Patches are augmented so that the network does not learn our
renderer's look alone: scale, rotation and mirror, colour gain, gamma and offset, blur,
sensor noise, JPEG re-compression, a prior eroded or grown by a pixel or two, and a prior
that lost one end of the animal (``cut_prior``). A tenth of
the clips is held out and scored as the tracker would use the network (whole windows, the
component attached to the prior), against the prior itself, and by how far its outline lies
from the true one (``evaluate.outline_offset_px``).
"""

import hashlib
import json
import math
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path

import cv2
import numpy as np
import torch
from torch.nn import functional as F

from dolphinfit.core.errors import InputError
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.progress import Progress, ProgressCallback
from dolphinfit.core.segment.edge_data import (
    TRAINING_SET, WINDOW_RECIPE, WINDOWS_PER_FRAME, Window, clip_windows,
    load_windows, save_windows, training_clip, training_configs,
)
from dolphinfit.core.segment.edge_net import (
    CHANNELS, EdgeNet, EdgeWeights, LearnedEdges, net_input, save_weights, water_of,
)
from dolphinfit.core.segment.evaluate import outline_offset_px
from dolphinfit.core.segment.salient import SalientNet
from dolphinfit.core.segment.seed import dilate, erode
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.sample import cache_dir

WINDOWS_STAGE, TRAIN_STAGE = "windows", "train"
HOLD_OUT_EVERY = 10   # every 10th clip is held out for validation
CHECK_EVERY = 250     # steps between scores on held-out windows
PRIOR_CUT_SHARE = 0.25        # patches whose prior lost one end (``cut_prior``)
PRIOR_CUT_KEEP = (0.45, 0.85)


@dataclass(frozen=True)
class TrainSettings:
    """How the edge network is trained (defaults: the bundled weights)."""

    clips: int = 150
    hard_clips: int = 60           # of edge_data.HARD_SCENES
    seed: int = 0
    steps: int = 5000
    batch: int = 12
    patch_px: int = 160
    learning_rate: float = 2e-3
    final_learning_rate: float = 2e-5
    boundary_share: float = 0.7    # patches centred on an outline, else anywhere
    dice_weight: float = 0.5


def windows_path(root: Path, config: SynthConfig) -> Path:
    """The windows file of a clip: named by its seed and a digest of its configuration and
    of how windows are cut, so a changed recipe never reads old windows."""
    recipe = json.dumps([config.to_json(), WINDOW_RECIPE], sort_keys=True)
    return root / f"windows_{config.seed}_{hashlib.sha256(recipe.encode()).hexdigest()[:12]}.npz"


def _windows_of(args: tuple[SynthConfig, Path, Path]) -> None:
    config, root, out = args
    torch.set_num_threads(1)
    if out.exists():
        return
    files = training_clip(config, root)
    net = SalientNet()
    windows = []
    for repeat in range(WINDOWS_PER_FRAME):
        windows += clip_windows(files, config.seed * WINDOWS_PER_FRAME + repeat, net)
    save_windows(windows, out)


def make_windows(settings: TrainSettings, workers: int = 2,
                 progress: ProgressCallback | None = None) -> list[Path]:
    """The windows file of every training clip, made where missing (module doc)."""
    root = cache_dir() / TRAINING_SET
    configs = training_configs(settings.clips, settings.seed, settings.hard_clips)
    jobs = [(config, root, windows_path(root, config)) for config in configs]
    with ProcessPoolExecutor(max_workers=workers) as pool:
        for done, _ in enumerate(pool.map(_windows_of, jobs), start=1):
            if progress is not None:
                progress(Progress(WINDOWS_STAGE, done, len(jobs)))
    return [out for _, _, out in jobs]


def _photometric(rgb: np.ndarray, gain: np.ndarray, offset: np.ndarray,
                 gamma: float) -> np.ndarray:
    """The pointwise part of the colour augmentation, on float RGB in 0…1."""
    return np.clip(rgb * gain + offset, 0, 1) ** gamma


def _region(image: np.ndarray, row0: int, col0: int, side: int) -> np.ndarray:
    """``side`` square of ``image`` from (row0, col0), zero where it lies outside."""
    out = np.zeros((side, side) + image.shape[2:], image.dtype)
    rows = slice(max(row0, 0), min(row0 + side, image.shape[0]))
    cols = slice(max(col0, 0), min(col0 + side, image.shape[1]))
    if rows.start < rows.stop and cols.start < cols.stop:
        out[rows.start - row0:rows.stop - row0, cols.start - col0:cols.stop - col0] = \
            image[rows, cols]
    return out


def cut_prior(prior: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """The prior with one end cut off across its long axis, keeping 45–85 % of its length
    from the other end: the salient network often gives only the front of an animal whose
    tail lies in glitter or deeper, and the outline must grow back to the whole animal. An
    empty prior stays empty."""
    if not prior.any():
        return prior
    rows, cols = np.nonzero(prior)
    points = np.stack([cols, rows], axis=1).astype(np.float64)
    centred = points - points.mean(axis=0)
    axis = np.linalg.eigh(centred.T @ centred)[1][:, -1]
    along = centred @ axis * rng.choice([-1.0, 1.0])
    low, high = along.min(), along.max()
    keep = along <= low + rng.uniform(*PRIOR_CUT_KEEP) * (high - low)
    cut = np.zeros_like(prior)
    cut[rows[keep], cols[keep]] = True
    return cut


def _centre(window: Window, boundary_share: float, rng: np.random.Generator) -> np.ndarray:
    """(row, col) a patch is centred on: a pixel on the true outline (jittered) or anywhere."""
    height, width = window.target.shape
    outline = np.argwhere(cv2.morphologyEx(window.target.astype(np.uint8), cv2.MORPH_GRADIENT,
                                           np.ones((3, 3), np.uint8)) > 0)
    if len(outline) and rng.random() < boundary_share:
        spread = max(height, width) // 8
        return outline[rng.integers(len(outline))] + rng.integers(-spread, spread + 1, 2)
    return np.array([rng.integers(height), rng.integers(width)])


def training_patch(window: Window, patch_px: int, boundary_share: float,
                   rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One augmented patch of a window (module doc): the (5, P, P) network input, the (P, P)
    target and where the patch lies inside the window (the rest is padding, not scored).

    The window is scaled by 0.75–1.33; only the region the patch needs is cut and resized.
    The input is normalised to the whole window's water (``edge_net.water_of``), taken from
    every fourth pixel after the same pointwise colour change."""
    scale = math.exp(rng.uniform(math.log(0.75), math.log(1.33)))
    gain, offset = np.exp(rng.normal(0, 0.08, 3)), rng.normal(0, 0.03, 3)
    gamma = math.exp(rng.normal(0, 0.15))
    prior_full = window.prior if rng.random() >= PRIOR_CUT_SHARE else cut_prior(window.prior, rng)
    sample = window.crop_rgb[::4, ::4].astype(np.float32) / 255.0
    centre, spread = water_of(_photometric(sample, gain, offset, gamma))
    side = int(math.ceil(patch_px / scale)) + 2
    row0, col0 = (_centre(window, boundary_share, rng) - side // 2).tolist()
    size = (patch_px, patch_px)
    shrink = scale < 1.0

    def resized(image: np.ndarray) -> np.ndarray:
        return cv2.resize(image, size,
                          interpolation=cv2.INTER_AREA if shrink else cv2.INTER_LINEAR)

    rgb = resized(_region(window.crop_rgb, row0, col0, side).astype(np.float32) / 255.0)
    saliency = resized(_region(window.saliency, row0, col0, side).astype(np.float32) / 255.0)
    prior = resized(_region(prior_full, row0, col0, side).astype(np.float32)) >= 0.5
    target = resized(_region(window.target, row0, col0, side).astype(np.float32)) >= 0.5
    inside = np.ones(window.target.shape, np.float32)
    valid = resized(_region(inside, row0, col0, side)) >= 0.999
    rgb = _photometric(rgb, gain, offset, gamma)
    if rng.random() < 0.3:
        rgb = cv2.GaussianBlur(rgb, (0, 0), rng.uniform(0.3, 1.0))
    if rng.random() < 0.5:
        rgb = rgb + rng.normal(0, rng.uniform(0, 0.015), rgb.shape).astype(np.float32)
    rgb8 = np.clip(rgb * 255 + 0.5, 0, 255).astype(np.uint8)
    if rng.random() < 0.3:
        ok, data = cv2.imencode(".jpg", rgb8,
                                [cv2.IMWRITE_JPEG_QUALITY, int(rng.integers(40, 91))])
        rgb8 = cv2.imdecode(data, cv2.IMREAD_UNCHANGED) if ok else rgb8
    if rng.random() < 0.2:
        grow = int(rng.integers(1, 3))
        prior = dilate(prior, grow) if rng.random() < 0.5 else erode(prior, grow)
    x = net_input(rgb8, saliency, prior, (centre, spread))
    x[:, ~valid] = 0.0
    quarter_turns = int(rng.integers(4))
    flip = rng.random() < 0.5
    arrays = [np.rot90(a, quarter_turns, axes=(-2, -1)) for a in (x, target, valid)]
    if flip:
        arrays = [a[..., ::-1] for a in arrays]
    x, target, valid = arrays
    return (np.ascontiguousarray(x), np.ascontiguousarray(target, dtype=np.float32),
            np.ascontiguousarray(valid, dtype=np.float32))


def loss_of(logits: torch.Tensor, target: torch.Tensor, valid: torch.Tensor,
            dice_weight: float) -> torch.Tensor:
    """Binary cross-entropy plus ``dice_weight`` × (1 − soft Dice), over valid pixels."""
    bce = F.binary_cross_entropy_with_logits(logits, target, weight=valid, reduction="sum")
    bce = bce / valid.sum().clamp(min=1.0)
    probability = torch.sigmoid(logits) * valid
    dice = (2 * (probability * target).sum() + 1) / (probability.sum() + target.sum() + 1)
    return bce + dice_weight * (1 - dice)


def held_out_scores(edges: LearnedEdges, windows: list[Window]) -> dict[str, float]:
    """Over whole windows: the mean IoU of the network's outline and of the prior alone, and
    the mean size and mean of the network's outline offset (px)."""
    network, prior, offsets = [], [], []
    for window in windows:
        saliency = window.saliency.astype(np.float32) / 255.0
        outlined = edges(window.crop_rgb, saliency, window.prior)
        network.append(mask_iou(outlined, window.target))
        prior.append(mask_iou(window.prior, window.target))
        offsets.append(outline_offset_px(outlined, window.target))
    return {"held_out_iou": float(np.mean(network)), "prior_iou": float(np.mean(prior)),
            "held_out_abs_offset_px": float(np.mean(np.abs(offsets))),
            "held_out_offset_px": float(np.mean(offsets))}


def train(train_windows: list[Window], held_out: list[Window], settings: TrainSettings,
          progress: ProgressCallback | None = None, log: Callable[[str], None] = print,
          device: torch.device | str = "cpu") -> tuple[EdgeNet, dict]:
    """The network fitted to ``train_windows`` (module doc) on ``device`` (core.device; the
    patches are cut on the CPU), and a record of the run."""
    torch.manual_seed(settings.seed)
    rng = np.random.default_rng([settings.seed, 29])
    net = EdgeNet(CHANNELS).to(device)   # initialised on the CPU: the same start anywhere
    optimiser = torch.optim.Adam(net.parameters(), lr=settings.learning_rate)
    decay = (settings.final_learning_rate / settings.learning_rate) ** (1 / settings.steps)
    scheduler = torch.optim.lr_scheduler.ExponentialLR(optimiser, decay)
    start, losses, checks = time.perf_counter(), [], []
    for step in range(1, settings.steps + 1):
        net.train()
        batch = [training_patch(train_windows[rng.integers(len(train_windows))],
                                settings.patch_px, settings.boundary_share, rng)
                 for _ in range(settings.batch)]
        x, y, valid = (torch.from_numpy(np.stack(parts)).to(device)
                       for parts in zip(*batch, strict=True))
        loss = loss_of(net(x)[:, 0], y, valid, settings.dice_weight)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        scheduler.step()
        losses.append(loss.item())
        if step % CHECK_EVERY == 0 or step == settings.steps:
            net.eval()  # on the way, a quarter of the held-out windows; at the end all
            scored = held_out if step == settings.steps else held_out[::4]
            scores = held_out_scores(LearnedEdges(EdgeWeights(net, {}), device=device),
                                     scored)
            checks.append({"step": step, "loss": float(np.mean(losses[-CHECK_EVERY:])),
                           "windows": len(scored), **scores})
            log(f"step {step}: loss {checks[-1]['loss']:.4f}, held-out IoU "
                f"{scores['held_out_iou']:.4f} (prior {scores['prior_iou']:.4f}), outline "
                f"offset {scores['held_out_offset_px']:+.3f} px (mean size "
                f"{scores['held_out_abs_offset_px']:.3f}), {time.perf_counter() - start:.0f} s")
        if progress is not None:
            progress(Progress(TRAIN_STAGE, step, settings.steps))
    net.eval()
    record = {"settings": asdict(settings), "channels": list(CHANNELS),
              "train_windows": len(train_windows), "held_out_windows": len(held_out),
              "checks": checks, "seconds": round(time.perf_counter() - start, 1),
              "torch": torch.__version__}
    return net, record


def split(paths: list[Path]) -> tuple[list[Window], list[Window]]:
    """Training and held-out windows: every ``HOLD_OUT_EVERY``-th clip is held out."""
    train_windows, held_out = [], []
    for index, path in enumerate(paths):
        (held_out if index % HOLD_OUT_EVERY == HOLD_OUT_EVERY - 1 else train_windows).extend(
            load_windows(path))
    return train_windows, held_out


def train_edges(settings: TrainSettings, out: Path, workers: int = 2,
                progress: ProgressCallback | None = None, log: Callable[[str], None] = print,
                device: torch.device | str = "cpu") -> dict:
    """The whole recipe: windows (on the CPU), training on ``device``, weights written to
    ``out``; returns the record."""
    paths = make_windows(settings, workers, progress)
    train_windows, held_out = split(paths)
    if not train_windows or not held_out:
        raise InputError(f"edge network training: {len(train_windows)} training and "
                         f"{len(held_out)} held-out windows from {len(paths)} clips; both "
                         f"need some (more --clips)")
    log(f"{len(train_windows)} training windows, {len(held_out)} held out")
    net, record = train(train_windows, held_out, settings, progress, log, device)
    save_weights(net, record, out)
    return record
