"""The network tracker: the salient-object network on a crop around the animal, frame by frame.

Colour alone fails on real water (light-grey animals over green water lose their flukes and
tail stock to the water's colour); a network that has learnt what an object looks like keeps
them. From the seed frame it tracks forwards to the end of the clip, then backwards, like the
built-in tracker, on every frame or only on chosen ones (the frames a fit will use):

1. **Window**: a square crop around the last mask moved by the last motion, its side the
   mask's longer side plus ``context`` of it on each side (the network hesitates less with
   water all round the animal: on windows around the suite's true masks, 0.5 gave a mean
   IoU of 0.859 against 0.846 for 0.25).
2. **Saliency** of the crop (``salient.SalientNet``). Once the animal's motion is known, what
   lies more than ``focus_fraction`` of its length from the prediction (another animal,
   glitter, seagrass) is faded into the water's colour first (``faded``). The network marks
   one object; when that is not the animal asked for, the other is painted out and the crop
   looked at again.
   Pixels with saliency ≥ ``threshold``: the component that overlaps the prediction (at the
   seed: under the click) with parts a seam cuts off; a neighbour touching the animal is
   split off (``nearer_to``, ``own_body``). Other animals seen beside it in the last look
   (``Seen.others``) move with it; what lies nearer to them than to the prediction is
   theirs, so that two animals touching only at their flukes each keep their own.
3. **Edges**: the network sees the crop at 320 px, coarser than the frame, and misses what
   shows faintly (fluke lobes a little under the surface). By default the edge network
   (``edge_net.LearnedEdges``) draws the outline again at the frame's resolution from the
   crop, the saliency and the chosen component; with ``edges="colour"`` each pixel within
   ``band_px`` of the outline is re-decided by the colour coverage of the animal against the
   water (``ColourEdges``: ``colour.coverage``, models from the mask's rim and ring).
4. **Moved**: a mask that overlaps its prediction less than ``follow_iou`` is read again
   from the same look, not kept near the prediction; where that look's window or its fading
   may have cut the animal (``View.shows_whole``), the network looks again in a window
   around both instead (on the suite's clips the new look repeated the first window's
   reading to an IoU of 0.97–0.99 in most steps, at the cost of a second pass of the
   network). Of the two masks, the plausible one whose area is closest to the animal's.
   Plausible: an area within ``lost_area_ratio`` … ``max_area_ratio`` of the animal's, and
   colours at least ``lost_separation_ratio`` as far from the water's as the animal's; both
   references run over the accepted frames, as the ground under the animal changes (held to
   the seed frame's contrast on light sand, an animal that swam into dark seagrass was
   refused in its right masks and lost). Where neither is plausible (the network merged
   the animal with glitter or seagrass), the colour tracker's step from the last frame's
   colours (``tracker.colour_follow``) may be.
5. **Lost** when no mask is plausible; then the whole frame is searched as the scan searches
   it (``auto_seed.find_animals``), for the animal of about its area nearest to where it was
   last seen (a look around where it was lost misses an animal that dived and came up
   elsewhere), and again every ``LOOK_AGAIN_EVERY`` frames it stays lost; between those, the
   last window grown by ``search_growth`` is searched each frame for a mask of about the
   reference area.
6. **On the edge**: the networks learnt where an outline lies from one renderer's blur and
   contrast; each frame's mask has its outline moved to where the image's own step from body
   to water is half-way (``outline_fit``; ``fit_outline``). The tracking itself follows the
   masks as the networks drew them.

The seed (a click, a box or the automatic seed) and the working scale at which a large
animal is tracked are ``net_seed``'s; the look at one window is ``net_look``'s; the loop over
the frames is ``tracking_loop``'s.
"""

import threading
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from dolphinfit.core.io.masks import MaskTrack
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.progress import ProgressCallback, check_cancel
from dolphinfit.core.segment.auto_seed import describe, find_animals
from dolphinfit.core.segment.colour import ColourModel, separation
from dolphinfit.core.segment.edge_steps import EdgeStep
from dolphinfit.core.segment.net_look import NetLook, Seen
from dolphinfit.core.segment.net_seed import NetSeeder
from dolphinfit.core.segment.net_settings import NetSettings
from dolphinfit.core.segment.outline_fit import refine_outline
from dolphinfit.core.segment.regions import centroid, models_near, shifted, window
from dolphinfit.core.segment.salient import SalientNet
from dolphinfit.core.segment.seed import dilate
from dolphinfit.core.segment.segmenter import AutoSeed, Frames, Seed
from dolphinfit.core.segment.tracker import TrackerSettings, colour_follow
from dolphinfit.core.segment.tracking_loop import check_seed_frame, track_both_ways, track_of
from dolphinfit.core.segment.windows import longer_side
from dolphinfit.core.segment.working_scale import ScaledFrames, upscaled

BACKEND_NAME = "network (U²-Net small)"
COLOUR_SETTINGS = TrackerSettings()  # the colour tracker's, for frames the network misses
OUTLINE_MARGIN_PX = 12               # the outline is fitted in the mask's box grown by this
LOOK_AGAIN_EVERY = 5                 # frames lost between searches of the whole frame


@dataclass
class _State:
    """What one tracking pass carries from frame to frame."""

    mask: np.ndarray | None            # last accepted (H, W) bool mask; None while lost
    last_seen: np.ndarray              # last accepted mask, kept while lost
    area_px: float                     # the animal's, running over the accepted masks
    reference_separation: float        # its colours' from the water's, running likewise
    animal: ColourModel                # colours of the last accepted mask and around it
    water: ColourModel
    velocity_px: np.ndarray = field(default_factory=lambda: np.zeros(2))
    moving: bool = False               # whether velocity_px was measured
    lost_steps: int = 0
    others: np.ndarray | None = None   # other animals seen beside it in the last look


class NetTracker:
    """The network tracker (implements ``Segmenter``); see the module doc."""

    def __init__(self, settings: NetSettings = NetSettings(),
                 only_frames: Sequence[int] | None = None,
                 net: SalientNet | None = None, edges: EdgeStep | None = None) -> None:
        """``only_frames``: segment just these frame indices (the seed frame is always
        segmented); the others are reported not visible. ``net``, ``edges``: a loaded network
        and outline step to share (default: those ``settings`` name, loaded)."""
        self.settings = settings
        self.only_frames = None if only_frames is None else sorted(set(only_frames))
        self.look = NetLook(settings, net, edges)
        self.seeder = NetSeeder(self.look)

    def segment(self, frames: Frames, seed: Seed, progress: ProgressCallback | None = None,
                cancel: threading.Event | None = None) -> MaskTrack:
        """Masks for the chosen frames of ``frames``, tracked from ``seed``.

        InputError if the seed finds no animal; core.progress.Cancelled once ``cancel`` is set
        (TrackingCancelled, with the frames tracked, once tracking has begun).
        """
        num_frames = len(frames)
        check_seed_frame(seed, num_frames)
        chosen = range(num_frames) if self.only_frames is None else \
            [t for t in self.only_frames if 0 <= t < num_frames]
        check_cancel(cancel)
        found, note = None, ""
        if isinstance(seed, AutoSeed):
            seed, animals = self.seeder.scan(frames, seed, chosen, cancel)
            found, note = animals[0].mask, "; " + describe(animals, seed.frame_idx)
        first = frames[seed.frame_idx]
        height, width = first.shape[:2]
        scale, mask = self.seeder.at_working_scale(first, seed, found)
        if scale < 1.0:
            frames = ScaledFrames(frames, scale, height, width)
            first = frames[seed.frame_idx]
        animal, water = models_near(first, mask)
        fitted = ", outline on the image's edge" if self.settings.fit_outline else ""
        source = f"{BACKEND_NAME}, {self.look.edges.name}{fitted}, from {seed}{note}" + (
            f"; tracked at {scale:.3g}× (the animal is longer than "
            f"{self.settings.max_length_px} px)" if scale < 1.0 else "")
        seen_height, seen_width = first.shape[:2]
        paste = None if scale >= 1.0 else (lambda crop: upscaled(
            crop.paste(seen_height, seen_width), height, width))
        return track_both_ways(
            frames, seed.frame_idx, self._on_edge(first, mask), chosen,
            lambda: _State(mask, mask, float(mask.sum()), separation(animal, water), animal,
                           water),
            lambda frame_rgb, state: self._on_edge(frame_rgb, self._next(frame_rgb, state)),
            lambda crops: track_of(crops, num_frames, width, height, source, paste),
            progress, cancel)

    def _on_edge(self, frame_rgb: np.ndarray, mask: np.ndarray | None) -> np.ndarray | None:
        """The frame's mask with its outline where the image puts it (step 6)."""
        if mask is None or not self.settings.fit_outline:
            return mask
        rows, cols = window(mask, OUTLINE_MARGIN_PX)
        fitted = mask.copy()
        fitted[rows, cols] = refine_outline(frame_rgb[rows, cols], mask[rows, cols]).mask
        return fitted

    def _next(self, frame_rgb: np.ndarray, state: _State) -> np.ndarray | None:
        """The mask in the next chosen frame (None if lost), updating ``state``."""
        settings = self.settings
        if state.mask is not None:
            prediction = shifted(state.mask, state.velocity_px)
            growth = 1.0
        else:
            prediction = state.last_seen
            growth = settings.search_growth ** min(state.lost_steps, 3)
        seen = None
        if prediction.any():
            near_window = self.look.around(frame_rgb, prediction, growth)
            if growth > 1.0:
                prediction = np.zeros_like(prediction)
                prediction[near_window] = True
            # fading out needs to know where the animal can be: not before its motion is
            focus_px = (round(settings.focus_fraction * longer_side(state.last_seen))
                        if state.moving else None)
            near_focus = None if focus_px is None else dilate(prediction, focus_px)
            others = (shifted(state.others, state.velocity_px)
                      if state.mask is not None and state.others is not None else None)
            first = self.look.look_at(frame_rgb, *near_window, prediction, focus=near_focus,
                                      others=others)
            found = first.mask
            candidates = [first]
            if not found.any() or mask_iou(found, prediction) < settings.follow_iou:
                # moved off its prediction: read the look again from what it found, not
                # kept near the prediction; where the window or its fading may have cut
                # the animal (the network loses what the window cuts), look again around
                # both, or wider
                again = (self.look.read(first.view, found, near=False, others=others)
                         if found.any() else None)
                if again is None or not first.view.shows_whole(again.mask):
                    anchor = found if found.any() else prediction
                    both = found | prediction
                    wider = 1.0 if found.any() else settings.search_growth
                    again = self.look.look_at(
                        frame_rgb, *self.look.around(frame_rgb, both, wider), anchor,
                        near=False, focus=None if focus_px is None else dilate(both, focus_px),
                        others=others)
                candidates.append(again)
            animals = [c for c in candidates if self._is_animal(frame_rgb, c.mask, state)]
            if animals:  # the one whose area is closest to the animal's
                seen = min(animals, key=lambda c: abs(np.log(np.count_nonzero(c.mask)
                                                             / state.area_px)))
            elif state.mask is not None:  # tracked until now: try its colours
                by_colour = colour_follow(frame_rgb, prediction, state.animal, state.water,
                                          COLOUR_SETTINGS)
                if self._is_animal(frame_rgb, by_colour, state):
                    seen = Seen(by_colour, np.zeros_like(by_colour))
        if seen is None and state.lost_steps % LOOK_AGAIN_EVERY == 0:
            seen = self._found_again(frame_rgb, state)
        mask = None if seen is None else seen.mask
        if mask is None:
            state.mask = None
            state.lost_steps += 1
            return None
        state.moving = state.mask is not None
        state.velocity_px = (centroid(mask) - centroid(state.mask) if state.moving
                             else np.zeros(2))
        state.mask = state.last_seen = mask
        state.others = seen.others if seen.others.any() else None
        state.animal, state.water = models_near(frame_rgb, mask)
        state.area_px = _blended(state.area_px, float(np.count_nonzero(mask)),
                                 settings.model_rate)
        state.reference_separation = _blended(state.reference_separation,
                                              separation(state.animal, state.water),
                                              settings.model_rate)
        state.lost_steps = 0
        return mask

    def _found_again(self, frame_rgb: np.ndarray, state: _State) -> Seen | None:
        """The animal looked for in the whole frame as the scan looks (step 5): of the animals
        of about its area there, the one nearest to where it was last seen, looked at again
        by the network; None where none is."""
        candidates = find_animals(frame_rgb, self.look.net.saliency, self.settings.tile_fraction,
                                  self.settings.threshold)
        low, high = self.settings.reacquire_area_range
        near = [c for c in candidates
                if low * state.area_px <= np.count_nonzero(c.mask) <= high * state.area_px]
        if not near:
            return None
        last = centroid(state.last_seen)
        best = min(near, key=lambda c: float(np.hypot(*np.subtract(c.centre_px(), last))))
        seen = self.look.look_at(frame_rgb, *self.look.around(frame_rgb, best.mask), best.mask,
                                 near=False)
        return seen if self._is_animal(frame_rgb, seen.mask, state) else None

    def _is_animal(self, frame_rgb: np.ndarray, mask: np.ndarray, state: _State) -> bool:
        """Enough area, not too much, and enough colour contrast to the water."""
        settings = self.settings
        area = np.count_nonzero(mask)
        low, high = (settings.reacquire_area_range if state.mask is None
                     else (settings.lost_area_ratio, settings.max_area_ratio))
        if not max(1.0, low * state.area_px) <= area <= high * state.area_px:
            return False
        contrast = separation(*models_near(frame_rgb, mask))
        return contrast >= settings.lost_separation_ratio * state.reference_separation


def _blended(reference: float, value: float, rate: float) -> float:
    """A running reference moved ``rate`` of the way to a new frame's ``value``."""
    return (1 - rate) * reference + rate * value
