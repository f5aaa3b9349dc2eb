"""The edge network: a small U-Net that draws the animal's outline in the tracker's window.

The salient-object network finds the animal but draws its outline coarsely (it sees the window
at 320 px) and leaves out what shows faintly: fluke lobes and flippers a little under the
surface, a tail stock in glitter. This network looks at the window at the frame's own
resolution, with the salient network's probability and the tracker's chosen component (the
*prior*, which says which animal is meant), and gives the probability that each pixel is that
animal. It was trained by the project on synthetic clips drawn at random from a wide range of
water, light, animals and companions, none of them the bench suite's (``edge_training``;
``dolphinfit train edges`` makes the weights again).

Input channels (``net_input``): the window's RGB less its median colour (the water), divided
by its spread; the salient probability; the prior (0/1). Windows larger than
``MAX_SIDE_PX`` are looked at downscaled and the probability scaled back up. The network runs
on the prior's bounding box grown by ``REACH_PX`` only, with the whole window's water: what
lies farther from the prior is not the animal (on 50 windows of the suite's clips, 1080p and
4K, the masks were those of the whole window to the pixel, from 0.46 of its pixels; at 48 px
one window differed by 0.03 % of its mask, at 32 px eleven).
"""

import json
import zipfile
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
import torch
from torch import nn
from torch.nn import functional as F

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.resources import RESOURCES_DIR
from dolphinfit.core.segment.regions import attached

WEIGHTS_PATH = RESOURCES_DIR / "models" / "edge_net_v1.npz"
INPUT_CHANNELS = 5
CHANNELS = (8, 16, 32, 48)     # per level, full resolution first
# larger windows are looked at downscaled: 1080p windows are smaller; at 4K (windows of
# 820–1142 px) 448 took foam in (surface_splash: outline +2.50 px, IoU 0.879; at 1024: +0.48,
# 0.927) for 0.9 s a window more on two cores
MAX_SIDE_PX = 1024
MIN_SPREAD = 0.02              # floor of the RGB spread (flat windows)
THRESHOLD = 0.5                # probability at which a pixel is the animal
DEPTH_MULTIPLE = 2 ** (len(CHANNELS) - 1)
REACH_PX = 64                  # the network runs this far around the prior's box (module doc)
OUTSIDE_LOGIT = -30.0          # beyond it: not the animal


def _block(inputs: int, outputs: int) -> nn.Sequential:
    return nn.Sequential(
        nn.Conv2d(inputs, outputs, 3, padding=1, bias=False), nn.BatchNorm2d(outputs),
        nn.ReLU(inplace=True),
        nn.Conv2d(outputs, outputs, 3, padding=1, bias=False), nn.BatchNorm2d(outputs),
        nn.ReLU(inplace=True))


class EdgeNet(nn.Module):
    """U-Net: two 3×3 convolutions per level, max-pooling down, bilinear up with skips;
    one logit per pixel. It takes any size; sides that are multiples of ``DEPTH_MULTIPLE``
    (``padded_to_multiple``) keep every level aligned with its skip, as in training."""

    def __init__(self, channels: tuple[int, ...] = CHANNELS) -> None:
        super().__init__()
        self.down = nn.ModuleList()
        previous = INPUT_CHANNELS
        for width in channels:
            self.down.append(_block(previous, width))
            previous = width
        self.up = nn.ModuleList(_block(channels[level] + channels[level - 1], channels[level - 1])
                                for level in range(len(channels) - 1, 0, -1))
        self.head = nn.Conv2d(channels[0], 1, 1)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        skips = []
        for level, block in enumerate(self.down):
            if level:
                x = F.max_pool2d(x, 2)
            x = block(x)
            skips.append(x)
        for block, skip in zip(self.up, reversed(skips[:-1]), strict=True):
            x = F.interpolate(x, size=skip.shape[-2:], mode="bilinear", align_corners=False)
            x = block(torch.cat([x, skip], dim=1))
        return self.head(x)


def water_of(rgb: np.ndarray) -> tuple[np.ndarray, float]:
    """The median colour of a window (its water: the animal covers less than half) and the
    spread of its colours about it (at least ``MIN_SPREAD``), of float RGB in 0…1."""
    centre = np.median(rgb.reshape(-1, 3), axis=0)
    return centre, max(float((rgb - centre).std()), MIN_SPREAD)


def net_input(crop_rgb: np.ndarray, saliency: np.ndarray, prior: np.ndarray,
              water: tuple[np.ndarray, float] | None = None) -> np.ndarray:
    """(5, h, w) float32 input of a window: RGB normalised to its water (module doc; ``water``:
    ``water_of`` the whole window when this is a part of it), the salient probability and
    the prior."""
    rgb = crop_rgb.astype(np.float32) / 255.0
    centre, spread = water if water is not None else water_of(rgb)
    return np.concatenate([((rgb - centre) / spread).astype(np.float32).transpose(2, 0, 1),
                           saliency[None].astype(np.float32),
                           prior[None].astype(np.float32)])


def padded_to_multiple(x: torch.Tensor, multiple: int = DEPTH_MULTIPLE) -> torch.Tensor:
    """(N, C, h, w) padded at the bottom and right (replicated) to sides divisible by
    ``multiple``."""
    height, width = x.shape[-2:]
    pad_rows, pad_cols = -height % multiple, -width % multiple
    if not pad_rows and not pad_cols:
        return x
    return F.pad(x, (0, pad_cols, 0, pad_rows), mode="replicate")


def _reach(prior: np.ndarray) -> tuple[slice, slice]:
    """The prior's bounding box grown by ``REACH_PX``, in the window; its start on the
    whole window's grid of ``DEPTH_MULTIPLE`` (each level pools the same pixels together)."""
    if not prior.any():   # no animal meant: the whole window
        return slice(0, prior.shape[0]), slice(0, prior.shape[1])
    col0, row0, width, height = cv2.boundingRect(prior.astype(np.uint8))
    first_row = max(0, row0 - REACH_PX) // DEPTH_MULTIPLE * DEPTH_MULTIPLE
    first_col = max(0, col0 - REACH_PX) // DEPTH_MULTIPLE * DEPTH_MULTIPLE
    return (slice(first_row, min(prior.shape[0], row0 + height + REACH_PX)),
            slice(first_col, min(prior.shape[1], col0 + width + REACH_PX)))


@dataclass(frozen=True)
class EdgeWeights:
    """A trained network and what it was trained with."""

    net: EdgeNet
    meta: dict


def save_weights(net: EdgeNet, meta: dict, path: Path) -> None:
    """The network's parameters and buffers as float32 arrays, with ``meta`` as JSON."""
    arrays = {name: value.detach().cpu().numpy().astype(np.float32)
              for name, value in net.state_dict().items() if value.is_floating_point()}
    with atomic_path(path) as temporary:
        with open(temporary, "wb") as stream:
            np.savez(stream, meta=np.array(json.dumps(meta, sort_keys=True)), **arrays)


def load_weights(path: Path = WEIGHTS_PATH) -> EdgeWeights:
    """The network saved at ``path`` (``save_weights``), in eval mode."""
    if not Path(path).is_file():
        raise InputError(f"edge network weights {path}: not found (they come with dolphinfit; "
                         f"`dolphinfit train edges` makes them again)")
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            net = EdgeNet(tuple(meta["channels"]))
            state = net.state_dict()
            for name, value in state.items():
                if value.is_floating_point():
                    state[name] = torch.from_numpy(data[name])
            net.load_state_dict(state)
    except (OSError, ValueError, KeyError, RuntimeError, TypeError, zipfile.BadZipFile) as exc:
        raise InputError(f"edge network weights {path}: unreadable ({exc})") from exc
    return EdgeWeights(net.eval(), meta)


class LearnedEdges:
    """The tracker's outline step by the edge network (the module doc)."""

    name = "edge network"

    def __init__(self, weights: EdgeWeights | None = None, gap_px: int = 2,
                 device: torch.device | str = "cpu") -> None:
        """``weights``: the bundled ones by default; their network is moved to ``device``,
        where it runs (core.device)."""
        self.weights = weights if weights is not None else load_weights()
        self.device = torch.device(device)
        self.weights.net.to(self.device)
        self.gap_px = gap_px

    def probability(self, crop_rgb: np.ndarray, saliency: np.ndarray,
                    prior: np.ndarray) -> np.ndarray:
        """(h, w) float32 probability that each pixel of the window is the prior's animal."""
        height, width = prior.shape
        scale = min(1.0, MAX_SIDE_PX / max(height, width))
        if scale < 1.0:
            size = (max(1, round(width * scale)), max(1, round(height * scale)))
            crop_rgb = cv2.resize(crop_rgb, size, interpolation=cv2.INTER_AREA)
            saliency = cv2.resize(saliency.astype(np.float32), size,
                                  interpolation=cv2.INTER_AREA)
            prior = cv2.resize(prior.astype(np.float32), size,
                               interpolation=cv2.INTER_AREA) >= 0.5
        rows, cols = _reach(prior)
        water = water_of(crop_rgb.astype(np.float32) / 255.0)
        x = torch.from_numpy(net_input(crop_rgb[rows, cols], saliency[rows, cols],
                                       prior[rows, cols], water))[None].to(self.device)
        reach_height, reach_width = x.shape[-2:]
        with torch.inference_mode():
            reached = self.weights.net(padded_to_multiple(x))[0, 0, :reach_height, :reach_width]
        logits = np.full(prior.shape, OUTSIDE_LOGIT, np.float32)
        logits[rows, cols] = reached.cpu().numpy()
        if scale < 1.0:
            logits = cv2.resize(logits, (width, height), interpolation=cv2.INTER_LINEAR)
        return 1.0 / (1.0 + np.exp(-logits))

    def __call__(self, crop_rgb: np.ndarray, saliency: np.ndarray,
                 mask: np.ndarray) -> np.ndarray:
        """The animal that ``mask`` marks, outlined by the network; ``mask`` unchanged when it
        is empty or the network's outline does not touch it."""
        if not mask.any():
            return mask
        decided = self.probability(crop_rgb, saliency, mask) >= THRESHOLD
        outlined = attached(decided, mask, self.gap_px)
        return outlined if outlined.any() else mask
