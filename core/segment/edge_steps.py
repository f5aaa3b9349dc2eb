"""The network tracker's outline step (its module doc, step 3): the edge network's redraw,
or the pixels near the outline re-decided by colour coverage."""

from typing import TYPE_CHECKING, Protocol

import cv2
import numpy as np

from dolphinfit.core.limits import one_of
from dolphinfit.core.segment.colour import coverage, separation, to_lab
from dolphinfit.core.segment.net_settings import EDGE_STEPS, NetSettings
from dolphinfit.core.segment.regions import attached
from dolphinfit.core.segment.seed import colour_models, dilate, erode
from dolphinfit.core.segment.windows import MIN_WINDOW_PX

if TYPE_CHECKING:
    import torch

MAX_CROP_COVER = 0.5  # a mask over more of its crop than this leaves no water to model


class EdgeStep(Protocol):
    """The outline step (module doc, step 3): the animal that ``mask`` (the component chosen
    from the saliency) marks in the window, outlined again."""

    name: str

    def __call__(self, crop_rgb: np.ndarray, saliency: np.ndarray,
                 mask: np.ndarray) -> np.ndarray: ...


class ColourEdges:
    """The outline by colour coverage near the network's edge (``refine_edges``)."""

    name = "colour edges"

    def __init__(self, settings: NetSettings) -> None:
        self.settings = settings

    def __call__(self, crop_rgb: np.ndarray, saliency: np.ndarray,
                 mask: np.ndarray) -> np.ndarray:
        return refine_edges(crop_rgb, mask, self.settings)


def make_edge_step(settings: NetSettings, device: "torch.device | str" = "cpu") -> EdgeStep:
    """The outline step that ``settings.edges`` names; the edge network runs on ``device``."""
    one_of(settings.edges, EDGE_STEPS, "network tracker edges")
    if settings.edges == "colour":
        return ColourEdges(settings)
    from dolphinfit.core.segment.edge_net import LearnedEdges
    return LearnedEdges(gap_px=settings.gap_px, device=device)


def refine_edges(crop_rgb: np.ndarray, mask: np.ndarray, settings: NetSettings) -> np.ndarray:
    """``mask`` with the pixels within ``band_px`` of its outline re-decided by colour
    coverage ≥ 0.5 (module doc, step 3); unchanged where the colours do not separate."""
    if (settings.band_px <= 0 or min(mask.shape) < MIN_WINDOW_PX or not mask.any()
            or mask.mean() > MAX_CROP_COVER):
        return mask
    lab = to_lab(crop_rgb)
    animal, water = colour_models(lab, mask)
    if separation(animal, water) < settings.min_separation:
        return mask
    inner = erode(mask, settings.band_px)
    band = dilate(mask, settings.band_px) & ~inner
    cover = cv2.GaussianBlur(coverage(lab, animal, water), (0, 0), settings.smoothing_sigma_px)
    decided = inner | (band & (cover >= 0.5))
    return attached(decided, mask, 1)
