"""The network tracker's look at one window of a frame (``net_tracker`` module doc, steps 1–3):
the square window around a mask, the salient network's probability there (looked at again
with another animal painted out when it marks that one), the component attached to the
prediction, split from a neighbour touching it, and the outline drawn by the edge step."""

import numpy as np

from dolphinfit.core.segment.bodies import nearer_to, own_body
from dolphinfit.core.segment.edge_steps import EdgeStep, make_edge_step
from dolphinfit.core.segment.net_settings import PAIR_AREA_RATIO, NetSettings
from dolphinfit.core.segment.regions import attached, centroid
from dolphinfit.core.segment.salient import SalientNet
from dolphinfit.core.segment.seed import dilate
from dolphinfit.core.segment.windows import faded, longer_side, square_window, window_side


class NetLook:
    """The salient network and the edge step, looking at windows with ``settings``."""

    def __init__(self, settings: NetSettings = NetSettings(), net: SalientNet | None = None,
                 edges: EdgeStep | None = None) -> None:
        """``net``, ``edges``: a loaded network and outline step to share (default: those
        ``settings`` name, loaded)."""
        self.settings = settings
        self.net = net if net is not None else SalientNet()
        self.edges = edges if edges is not None else make_edge_step(settings)

    def masked_in(self, frame_rgb: np.ndarray, rows: slice, cols: slice,
                  prediction: np.ndarray, near: bool = True,
                  focus: np.ndarray | None = None) -> np.ndarray:
        """Steps 2 and 3 in one window: the (H, W) mask attached to ``prediction``, kept near
        it unless ``near`` is False (at the seed, or after the animal moved off its
        prediction, where the prediction may be only a part of the animal). ``focus``: where
        the animal can be; what lies beyond is faded out first."""
        settings = self.settings
        crop = np.ascontiguousarray(frame_rgb[rows, cols])
        local = prediction[rows, cols]
        mask = np.zeros(frame_rgb.shape[:2], bool)
        if not local.any():
            return mask
        length_px = longer_side(local)
        near_px = max(settings.min_near_px, round(settings.near_fraction * length_px))
        crop_seen = crop if focus is None else faded(
            crop, focus[rows, cols], settings.fade_fraction * length_px)
        saliency = self.saliency(crop_seen, local)
        salient = saliency >= settings.threshold
        found = attached(salient, local, settings.gap_px)
        beyond = found & ~dilate(local, near_px)
        expected_px = float(np.count_nonzero(local))
        if near and beyond.any() and np.count_nonzero(found) > PAIR_AREA_RATIO * expected_px:
            # a neighbour touching the animal: split between the two
            found = attached(nearer_to(found, local & found, beyond), local, settings.gap_px)
        elif found.any():
            found = own_body(found, local, saliency, expected_px)
        mask[rows, cols] = self.edges(crop, saliency, found)
        return mask

    def saliency(self, crop: np.ndarray, expected: np.ndarray) -> np.ndarray:
        """(h, w) saliency of a crop. The network marks one salient object, not necessarily
        the one asked for: when nothing salient meets ``expected`` (where the animal is: the
        click, the prediction) but something else is, that something (another animal) is
        painted over with the water's median colour and the crop looked at again."""
        threshold = self.settings.threshold
        saliency = self.net.saliency(crop)
        salient = saliency >= threshold
        if (salient & expected).any() or not salient.any():
            return saliency
        other = dilate(salient, self.settings.min_near_px)
        if other.all():
            return saliency
        painted = crop.copy()
        painted[other] = np.median(crop[~other], axis=0).astype(crop.dtype)
        return self.net.saliency(painted)

    def around(self, frame_rgb: np.ndarray, mask: np.ndarray,
               growth: float = 1.0) -> tuple[slice, slice]:
        """The square window around a mask (step 1)."""
        side = window_side(longer_side(mask), self.settings, growth)
        return square_window(centroid(mask), side, *frame_rgb.shape[:2])
