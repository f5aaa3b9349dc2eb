"""The network tracker's look at one window of a frame (``net_tracker`` module doc, steps 1–3):
the square window around a mask, the salient network's probability there (looked at again
with another animal painted out when it marks that one), the component attached to the
prediction, split from a neighbour touching it, the outline drawn by the edge step, and the
other animals the window shows beside it. The network's look (``View``) is kept apart from
its reading, so that a step can read a look again (``net_tracker`` step 4)."""

from dataclasses import dataclass

import cv2
import numpy as np

from dolphinfit.core.segment.auto_seed import cut_by_window
from dolphinfit.core.segment.bodies import MIN_CORE_SHARE, nearer_to, own_body
from dolphinfit.core.segment.edge_steps import EdgeStep, make_edge_step
from dolphinfit.core.segment.net_settings import PAIR_AREA_RATIO, NetSettings
from dolphinfit.core.segment.regions import attached, centroid
from dolphinfit.core.segment.salient import SalientNet
from dolphinfit.core.segment.seed import dilate, shape_of
from dolphinfit.core.segment.windows import faded, longer_side, square_window, window_side

# another animal beside the tracked one, as much of it as the look shows, is this many times
# its area and this elongated. On the suite's pairs the companions measured 0.3–1.2 times
# the area and 4.7–6.7 (a calf may be a third of its mother's area); a patch of sun glitter
# on glitter_heavy 6.5 times and 1.45.
OTHER_AREA_SHARES = (MIN_CORE_SHARE, 1 / MIN_CORE_SHARE)
OTHER_MIN_ELONGATION = 3.0


@dataclass(frozen=True, eq=False)
class View:
    """One look's window of a frame and what the salient network saw there: the crop as it is
    (the edge step draws on it), its (h, w) saliency, and ``unfaded``: where the look faded
    nothing (None: nowhere faded)."""

    rows: slice
    cols: slice
    crop: np.ndarray
    saliency: np.ndarray
    unfaded: np.ndarray | None
    frame_shape: tuple[int, int]

    def shows_whole(self, mask: np.ndarray) -> bool:
        """Whether a (frame-sized) mask read from this view lies where the view showed the
        frame as it is: off the window's sides (but those on the frame's edge) and inside
        what it did not fade. Where it does not, the window may have cut the animal."""
        inside = self.unfaded is None or not (mask[self.rows, self.cols] & ~self.unfaded).any()
        return inside and not cut_by_window(mask, self.rows, self.cols)


@dataclass(frozen=True, eq=False)
class Seen:
    """What one look at a window found: the animal's (H, W) bool mask, ``others``: the
    salient bodies in the window apart from it that look like other animals, and the
    ``view`` it was read from (None where no network look found it)."""

    mask: np.ndarray
    others: np.ndarray
    view: View | None = None


class NetLook:
    """The salient network and the edge step, looking at windows with ``settings``."""

    def __init__(self, settings: NetSettings = NetSettings(), net: SalientNet | None = None,
                 edges: EdgeStep | None = None) -> None:
        """``net``, ``edges``: a loaded network and outline step to share (default: those
        ``settings`` name, loaded)."""
        self.settings = settings
        self.net = net if net is not None else SalientNet()
        self.edges = edges if edges is not None else make_edge_step(settings)
        self._last_outline: tuple[View, np.ndarray, np.ndarray] | None = None

    def masked_in(self, frame_rgb: np.ndarray, rows: slice, cols: slice,
                  prediction: np.ndarray, near: bool = True,
                  focus: np.ndarray | None = None) -> np.ndarray:
        """``look_at``'s mask alone."""
        return self.look_at(frame_rgb, rows, cols, prediction, near, focus).mask

    def look_at(self, frame_rgb: np.ndarray, rows: slice, cols: slice,
                prediction: np.ndarray, near: bool = True, focus: np.ndarray | None = None,
                others: np.ndarray | None = None) -> Seen:
        """Steps 2 and 3 in one window: the network's look (``view``) and its reading
        (``read``). ``focus``: where the animal can be; what lies beyond is faded out
        first."""
        local = prediction[rows, cols]
        if not local.any():
            empty = np.zeros(frame_rgb.shape[:2], bool)
            return Seen(empty, empty.copy())
        return self.read(self.view(frame_rgb, rows, cols, local, focus), prediction, near,
                         others)

    def view(self, frame_rgb: np.ndarray, rows: slice, cols: slice, local: np.ndarray,
             focus: np.ndarray | None = None) -> View:
        """The network's look at a window where the animal is expected at ``local`` (in the
        window), what lies beyond ``focus`` (in the frame) faded out first."""
        crop = np.ascontiguousarray(frame_rgb[rows, cols])
        unfaded = None if focus is None else focus[rows, cols]
        crop_seen = crop if unfaded is None else faded(
            crop, unfaded, self.settings.fade_fraction * longer_side(local))
        return View(rows, cols, crop, self.saliency(crop_seen, local), unfaded,
                    frame_rgb.shape[:2])

    def read(self, view: View, prediction: np.ndarray, near: bool = True,
             others: np.ndarray | None = None) -> Seen:
        """The mask attached to ``prediction`` in a view, kept near it unless ``near`` is
        False (at the seed, or after the animal moved off its prediction, where the
        prediction may be only a part of the animal). ``others``: where other animals are
        predicted; salient pixels nearer to them than to ``prediction`` are theirs (two
        animals touching only at their flukes make one component that no stricter level
        parts, and a split by distance alone gives the nearer animal the other's flukes)."""
        settings, rows, cols, saliency = self.settings, view.rows, view.cols, view.saliency
        local = prediction[rows, cols]
        mask = np.zeros(view.frame_shape, bool)
        seen_others = np.zeros_like(mask)
        if not local.any():
            return Seen(mask, seen_others, view)
        near_px = max(settings.min_near_px, round(settings.near_fraction * longer_side(local)))
        all_salient = saliency >= settings.threshold
        theirs = _theirs(all_salient, local, others, rows, cols)
        salient = all_salient & ~theirs
        found = attached(salient, local, settings.gap_px)
        beyond = found & ~dilate(local, near_px)
        expected_px = float(np.count_nonzero(local))
        if near and beyond.any() and np.count_nonzero(found) > PAIR_AREA_RATIO * expected_px:
            # a neighbour touching the animal: split between the two
            found = attached(nearer_to(found, local & found, beyond), local, settings.gap_px)
        elif found.any():
            found = own_body(found, local, saliency, expected_px)
        mask[rows, cols] = self._outline(view, found) & ~theirs
        seen_others[rows, cols] = _bodies_apart(all_salient, mask[rows, cols], settings.gap_px)
        return Seen(mask, seen_others, view)

    def _outline(self, view: View, chosen: np.ndarray) -> np.ndarray:
        """The edge step's outline of the component ``chosen`` in a view. Read again, a view
        mostly gives the same component (60 of 67 times on the tuning split): its outline
        is the last one's."""
        last = self._last_outline
        if last is not None and last[0] is view and np.array_equal(last[1], chosen):
            return last[2]
        outlined = self.edges(view.crop, view.saliency, chosen)
        self._last_outline = (view, chosen, outlined)
        return outlined

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


def _theirs(salient: np.ndarray, local: np.ndarray, others: np.ndarray | None, rows: slice,
            cols: slice) -> np.ndarray:
    """The pixels of a window nearer to the other animals' predicted masks than to the
    animal's (``local``), where another animal predicted there is salient; else none. The
    edge step's outline is cut there too: drawn from a component that touches the other
    animal, it may run on into it."""
    other = np.zeros_like(salient) if others is None else others[rows, cols] & ~local
    own = local & ~other
    if not (other & salient).any() or not own.any():
        return np.zeros_like(salient)
    return ~nearer_to(np.ones_like(salient), own, other)


def _bodies_apart(salient: np.ndarray, mask: np.ndarray, gap_px: int) -> np.ndarray:
    """The salient components of a window outside the animal's mask (grown by ``gap_px``)
    that look like other animals (``Seen``): ``OTHER_AREA_SHARES`` of its area and at least
    ``OTHER_MIN_ELONGATION``."""
    rest = salient & ~dilate(mask, gap_px)
    count, labels, stats, _ = cv2.connectedComponentsWithStats(rest.astype(np.uint8),
                                                               connectivity=8)
    area = np.count_nonzero(mask)
    low, high = (share * area for share in OTHER_AREA_SHARES)
    bodies = [label for label in range(1, count)
              if low <= stats[label, cv2.CC_STAT_AREA] <= high
              and shape_of(labels == label)[1] >= OTHER_MIN_ELONGATION]
    return np.isin(labels, bodies) if bodies else np.zeros_like(salient)
