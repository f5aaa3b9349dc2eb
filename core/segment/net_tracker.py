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
   split off (``nearer_to``, ``own_body``).
3. **Edges**: the network sees the crop at 320 px, coarser than the frame, and misses what
   shows faintly (fluke lobes a little under the surface). By default the edge network
   (``edge_net.LearnedEdges``) draws the outline again at the frame's resolution from the
   crop, the saliency and the chosen component; with ``edges="colour"`` each pixel within
   ``band_px`` of the outline is re-decided by the colour coverage of the animal against the
   water (``ColourEdges``: ``colour.coverage``, models from the mask's rim and ring).
4. **Moved**: a mask that overlaps its prediction less than ``follow_iou`` is looked at again
   in a window around both; of the two, the plausible one (area within ``lost_area_ratio``
   … ``max_area_ratio`` of the animal's, colours apart from the water) whose area is closest
   to the animal's. Where neither is plausible (the network merged the animal with glitter
   or seagrass), the colour tracker's step from the last frame's colours
   (``tracker.colour_follow``) may be.
5. **Lost** when no mask is plausible; while lost, the last window grown by
   ``search_growth`` is searched each frame for a mask of about the reference area.

**Seed**: a click takes the salient component under it in a first window
(``first_window_fraction`` of the frame) or the built-in detector's dark blob there, whichever
looks more like a lone dolphin (``dolphin_unlikeness``: a dark animal over light sand is
hardly an object to the network), or the lone animal the network sees under it in the whole
frame where that holds the pick and more (a click on a whale's back). A box looks in a window
around it; the automatic seed (``auto_seed``) takes the best animal it finds in the seed's
frame or, where there is none, in the first of up to ``AUTO_SEED_FRAMES`` frames spread over
the clip that has one, and looks again around it (a new look that loses more than
``KEPT_SHARE`` of it is not taken: on a real minke whale the edge network dropped the tail
stock). Then, for up to ``seed_rounds``, the mask is looked at again in a window around
itself, wider while it is cut by its window's edge, as long as that makes it more elongated:
a dark animal beside seagrass otherwise grows into the seagrass round after round.

**Working scale**: an animal longer than ``max_length_px`` (a whale near the drone) is
tracked in frames downscaled until it fits (``working_scale``), its masks brought back to the
frame's size.
"""

import threading
from collections.abc import Sequence
from dataclasses import dataclass, field

import cv2
import numpy as np

from core.errors import InputError
from core.io.masks import MaskTrack
from core.iou import mask_iou
from core.progress import Progress, ProgressCallback, check_cancel
from core.segment.auto_seed import (
    Candidate, cut_by_window, describe, find_animals, is_animal_shaped, is_lone, scan_order,
)
from core.segment.bodies import dolphin_unlikeness, nearer_to, own_body
from core.segment.colour import ColourModel, separation
from core.segment.edge_steps import EdgeStep, make_edge_step
from core.segment.net_settings import PAIR_AREA_RATIO, NetSettings
from core.segment.regions import (
    MaskCrop,
    attached,
    centroid,
    crop_of,
    models_near,
    shifted,
)
from core.segment.salient import SalientNet
from core.segment.seed import POINT_SEARCH_FRACTION, dilate, seed_mask, shape_of
from core.segment.segmenter import (
    TRACK_STAGE,
    AutoSeed,
    BoxSeed,
    Frames,
    PointSeed,
    Seed,
)
from core.segment.tracker import TrackerSettings, colour_follow
from core.segment.windows import MIN_WINDOW_PX, faded, longer_side, square_window, window_side
from core.segment.working_scale import (
    ScaledFrames, downscaled, resized, scaled_seed, scaled_size, upscaled,
)

BACKEND_NAME = "network (U²-Net small)"
COLOUR_SETTINGS = TrackerSettings()  # the colour tracker's, for frames the network misses
KEPT_SHARE = 0.85          # the automatic seed's redraw keeps this much of what it found
AUTO_SEED_FRAMES = 12      # frames the automatic seed looks at before it gives up
WHOLE_SHARE = 0.8          # the whole frame's component must hold this much of a click's pick
SCALE_ROUNDS = 3           # looks at a large animal, each at the scale the last one asked for
SCALE_MARGIN = 0.9         # the working scale leaves the animal this much under the limit


@dataclass
class _State:
    """What one tracking pass carries from frame to frame."""

    mask: np.ndarray | None            # last accepted (H, W) bool mask; None while lost
    last_seen: np.ndarray              # last accepted mask, kept while lost
    area_px: float
    reference_separation: float
    animal: ColourModel                # colours of the last accepted mask and around it
    water: ColourModel
    velocity_px: np.ndarray = field(default_factory=lambda: np.zeros(2))
    moving: bool = False               # whether velocity_px was measured
    lost_steps: int = 0


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
        self.net = net if net is not None else SalientNet()
        self.edges = edges if edges is not None else make_edge_step(settings)

    def segment(self, frames: Frames, seed: Seed, progress: ProgressCallback | None = None,
                cancel: threading.Event | None = None) -> MaskTrack:
        """Masks for the chosen frames of ``frames``, tracked from ``seed``.

        InputError if the seed finds no animal; core.progress.Cancelled once ``cancel`` is set.
        """
        num_frames = len(frames)
        if not 0 <= seed.frame_idx < num_frames:
            raise IndexError(f"seed frame {seed.frame_idx} is outside the clip "
                             f"(0…{num_frames - 1})")
        chosen = range(num_frames) if self.only_frames is None else \
            [t for t in self.only_frames if 0 <= t < num_frames]
        check_cancel(cancel)
        found, note = None, ""
        if isinstance(seed, AutoSeed):
            seed, animals = self._scan(frames, seed, chosen, cancel)
            found, note = animals[0].mask, "; " + describe(animals, seed.frame_idx)
        forward = [t for t in chosen if t > seed.frame_idx]
        backward = [t for t in reversed(chosen) if t < seed.frame_idx]
        total = 1 + len(forward) + len(backward)
        first = frames[seed.frame_idx]
        height, width = first.shape[:2]
        scale, mask = self._seed_at_working_scale(first, seed, found)
        if scale < 1.0:
            frames = ScaledFrames(frames, scale, height, width)
            first = frames[seed.frame_idx]
        crops: dict[int, MaskCrop] = {seed.frame_idx: crop_of(mask)}
        done = 1
        if progress is not None:
            progress(Progress(TRACK_STAGE, done, total))
        animal, water = models_near(first, mask)
        for order in (forward, backward):
            state = _State(mask, mask, float(mask.sum()), separation(animal, water), animal,
                           water)
            for frame_idx in order:
                check_cancel(cancel)
                found = self._next(frames[frame_idx], state)
                if found is not None:
                    crops[frame_idx] = crop_of(found)
                done += 1
                if progress is not None:
                    progress(Progress(TRACK_STAGE, done, total))
        is_visible = np.array([t in crops for t in range(num_frames)])
        seen_height, seen_width = first.shape[:2]
        source = f"{BACKEND_NAME}, {self.edges.name}, from {seed}{note}" + (
            f"; tracked at {scale:.3g}× (the animal is longer than "
            f"{self.settings.max_length_px} px)" if scale < 1.0 else "")
        if scale < 1.0:
            return MaskTrack(is_visible, width, height, source, lambda t: upscaled(
                crops[t].paste(seen_height, seen_width), height, width))
        return MaskTrack(is_visible, width, height, source,
                         lambda t: crops[t].paste(height, width))

    def _scan(self, frames: Frames, seed: AutoSeed, chosen: Sequence[int],
              cancel: threading.Event | None) -> tuple[AutoSeed, list[Candidate]]:
        """The automatic seed on the first frame where it finds an animal, of the seed's
        frame and then up to ``AUTO_SEED_FRAMES`` others spread over the chosen frames (an
        animal under water or out of the frame at the start is found where it shows);
        InputError naming the frames searched when there is none in any."""
        tried = scan_order(chosen, seed.frame_idx, AUTO_SEED_FRAMES)
        for frame_idx in tried:
            check_cancel(cancel)
            animals = self._animals(frames[frame_idx], seed)
            if animals:
                return AutoSeed(frame_idx, seed.length_px), animals
        expected = ("" if seed.length_px is None else
                    f" {seed.length_px[0]:.0f}–{seed.length_px[1]:.0f} px long")
        raise InputError(f"the automatic seed found no animal{expected} in {len(tried)} "
                         f"frame{'s' if len(tried) > 1 else ''} searched "
                         f"({', '.join(str(t) for t in tried)}): click on the animal or draw "
                         f"a box around it instead")

    def _seed_at_working_scale(self, frame_rgb: np.ndarray, seed: Seed,
                               found: np.ndarray | None = None) -> tuple[float, np.ndarray]:
        """The working scale (``working_scale``; 1 for an animal up to ``max_length_px``
        long) and the seed mask at it. The animal's length comes from its mask, which a
        window may have cut short, so it is looked at again until it fits. ``found``: the
        automatic seed's animal in this frame."""
        height, width = frame_rgb.shape[:2]
        first = found if found is not None else self._first_look(frame_rgb, seed)
        scale = self._scale_for(first)
        for _ in range(SCALE_ROUNDS):
            seen = frame_rgb if scale == 1.0 else resized(frame_rgb,
                                                          scaled_size(height, width, scale))
            mask = self._seed_mask(seen, seed if scale == 1.0 else scaled_seed(seed, scale),
                                   first if scale == 1.0 else None if found is None
                                   else downscaled(found, seen.shape[:2]))
            if longer_side(mask) <= self.settings.max_length_px:
                break
            scale *= self._scale_for(mask)
        return scale, mask

    def _first_look(self, frame_rgb: np.ndarray, seed: Seed) -> np.ndarray:
        """A cheap first idea of the animal's extent, to pick the working scale before the
        seed's full look: the lone animal the network sees under a click in the whole
        frame, or a box."""
        whole_frame = (slice(0, frame_rgb.shape[0]), slice(0, frame_rgb.shape[1]))
        extent = np.zeros(frame_rgb.shape[:2], bool)
        if isinstance(seed, PointSeed) and 0 <= seed.x_px < frame_rgb.shape[1] and \
                0 <= seed.y_px < frame_rgb.shape[0]:
            extent = self._salient_at(frame_rgb, *whole_frame, seed, lone=True)
        elif isinstance(seed, BoxSeed):
            extent[seed.y_px:seed.y_px + seed.height_px,
                   seed.x_px:seed.x_px + seed.width_px] = True
        return extent

    def _scale_for(self, mask: np.ndarray) -> float:
        """The downscale that brings an animal of this mask under ``max_length_px``, with a
        margin; 1 when it is under it already (or unknown: an empty mask)."""
        length = longer_side(mask) if mask.any() else 0
        if length <= self.settings.max_length_px:
            return 1.0
        return SCALE_MARGIN * self.settings.max_length_px / length

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
        saliency = self._saliency(crop_seen, local)
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

    def _saliency(self, crop: np.ndarray, expected: np.ndarray) -> np.ndarray:
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

    def _around(self, frame_rgb: np.ndarray, mask: np.ndarray,
                growth: float = 1.0) -> tuple[slice, slice]:
        """The square window around a mask (module doc, step 1)."""
        side = window_side(longer_side(mask), self.settings, growth)
        return square_window(centroid(mask), side, *frame_rgb.shape[:2])

    def _seed_mask(self, frame_rgb: np.ndarray, seed: Seed,
                   found: np.ndarray | None = None) -> np.ndarray:
        """The animal in the seed frame: a click, a box or the automatic search finds it in
        a first window; then it is looked at again around itself (wider while cut by the
        window's edge), a new look kept where the mask was cut or where it is no less
        elongated (module doc, **Seed**). ``found``: what a first look at this frame found
        (the automatic seed's animal; for a click ``_first_look``'s, not looked for again)."""
        height, width = frame_rgb.shape[:2]
        if isinstance(seed, PointSeed):
            if not (0 <= seed.x_px < width and 0 <= seed.y_px < height):
                raise InputError(f"seed {seed}: outside the {width}x{height} px frame")
            side = max(MIN_WINDOW_PX, self.settings.first_window_fraction * min(height, width))
            rows, cols = square_window(np.array([seed.x_px, seed.y_px]), side, height, width)
            mask, (rows, cols) = self._clicked(frame_rgb, rows, cols, seed, found)
        elif isinstance(seed, BoxSeed):
            box = np.zeros((height, width), bool)
            box[seed.y_px:seed.y_px + seed.height_px, seed.x_px:seed.x_px + seed.width_px] = True
            rows, cols = self._around(frame_rgb, box)
            mask = self.masked_in(frame_rgb, rows, cols, box) & \
                dilate(box, self.settings.min_near_px)
        else:  # the tile shows the animal small: look again in a window around what it found
            animals = [] if found is not None else self._animals(frame_rgb, seed)
            mask = found if found is not None else (
                animals[0].mask if animals else np.zeros(frame_rgb.shape[:2], bool))
            rows, cols = self._around(frame_rgb, mask) if mask.any() else (slice(0), slice(0))
            again = self.masked_in(frame_rgb, rows, cols, mask, near=False)
            if np.count_nonzero(again & mask) >= KEPT_SHARE * np.count_nonzero(mask):
                mask = again   # a redraw that lost part of the animal is not taken
        growth = 1.0
        for _ in range(self.settings.seed_rounds):
            if not mask.any():
                break
            cut_off = cut_by_window(mask, rows, cols)
            if cut_off:
                growth *= self.settings.search_growth
            rows, cols = self._around(frame_rgb, mask, growth)
            again = self.masked_in(frame_rgb, rows, cols, mask, near=False)
            if isinstance(seed, BoxSeed):
                again &= dilate(box, self.settings.min_near_px)
            if not again.any():
                growth *= self.settings.search_growth  # the window may hold only the animal
                continue
            if np.array_equal(again, mask) or \
                    (not cut_off and shape_of(again)[1] < shape_of(mask)[1]):
                break
            mask, growth = again, 1.0
        if not mask.any():
            kind = "at the seed" if not isinstance(seed, AutoSeed) else "in the frame"
            raise InputError(f"frame {seed.frame_idx}: the network found no animal {kind} "
                             f"({seed})")
        return mask

    def _animals(self, frame_rgb: np.ndarray, seed: AutoSeed) -> list[Candidate]:
        """The animals the automatic seed finds in a frame, best first (``auto_seed``)."""
        return find_animals(frame_rgb, self.net.saliency, self.settings.tile_fraction,
                            self.settings.threshold, seed.length_px)

    def _clicked(self, frame_rgb: np.ndarray, rows: slice, cols: slice, seed: PointSeed,
                 whole: np.ndarray | None = None) -> tuple[np.ndarray, tuple[slice, slice]]:
        """The animal under a click and the window it was found in: the salient component
        under (or nearest to) it in the first window or the built-in detector's blob there
        (``seed.seed_mask``, in the whole frame: a dark animal over light sand, which the
        network may hardly see), whichever looks more like a lone dolphin
        (``dolphin_unlikeness``); but the animal the network sees in the whole frame under the
        click where that holds most of the pick and more (the first window lay inside a
        large animal, and each pick was a part of it; ``whole``: that animal where it was
        looked for already)."""
        whole_frame = (slice(0, frame_rgb.shape[0]), slice(0, frame_rgb.shape[1]))
        pick, window = self._salient_at(frame_rgb, rows, cols, seed), (rows, cols)
        try:
            by_colour = seed_mask(frame_rgb, seed)
        except InputError:  # no dark, elongated blob there
            by_colour = None
        if by_colour is not None and dolphin_unlikeness(by_colour) < dolphin_unlikeness(pick):
            pick, window = by_colour, whole_frame
        if whole is None:
            whole = self._salient_at(frame_rgb, *whole_frame, seed, lone=True)
        if (whole.any() and np.count_nonzero(whole) > np.count_nonzero(pick)
                and np.count_nonzero(whole & pick) >= WHOLE_SHARE * np.count_nonzero(pick)):
            return whole, whole_frame
        return pick, window

    def _salient_at(self, frame_rgb: np.ndarray, rows: slice, cols: slice,
                    seed: PointSeed, lone: bool = False) -> np.ndarray:
        """The salient component under (or nearest to) a click, in a window; with ``lone``
        only one shaped like a lone animal (``is_lone_animal``), else nothing."""
        crop = np.ascontiguousarray(frame_rgb[rows, cols])
        col, row = int(seed.x_px) - cols.start, int(seed.y_px) - rows.start
        clicked = np.zeros(crop.shape[:2], bool)
        clicked[row, col] = True
        saliency = self._saliency(crop, clicked)
        count, labels = cv2.connectedComponents(
            (saliency >= self.settings.threshold).astype(np.uint8), connectivity=8)
        mask = np.zeros(frame_rgb.shape[:2], bool)
        if count < 2:
            return mask
        label = labels[row, col]
        if label == 0:
            found_rows, found_cols = np.nonzero(labels)
            gaps = np.hypot(found_rows - row, found_cols - col)
            nearest = np.argmin(gaps)
            if gaps[nearest] > POINT_SEARCH_FRACTION * np.hypot(*frame_rgb.shape[:2]):
                return mask
            label = labels[found_rows[nearest], found_cols[nearest]]
        component = labels == label
        if lone and not (is_animal_shaped(component, frame_rgb.shape[0] * frame_rgb.shape[1])
                         and is_lone(component)):
            return mask
        mask[rows, cols] = own_body(component, clicked, saliency)
        return mask

    def _next(self, frame_rgb: np.ndarray, state: _State) -> np.ndarray | None:
        """The mask in the next chosen frame (None if lost), updating ``state``."""
        settings = self.settings
        if state.mask is not None:
            prediction = shifted(state.mask, state.velocity_px)
            growth = 1.0
        else:
            prediction = state.last_seen
            growth = settings.search_growth ** min(state.lost_steps, 3)
        mask = None
        if prediction.any():
            near_window = self._around(frame_rgb, prediction, growth)
            if growth > 1.0:
                prediction = np.zeros_like(prediction)
                prediction[near_window] = True
            # fading out needs to know where the animal can be: not before its motion is
            focus_px = (round(settings.focus_fraction * longer_side(state.last_seen))
                        if state.moving else None)
            near_focus = None if focus_px is None else dilate(prediction, focus_px)
            found = self.masked_in(frame_rgb, *near_window, prediction, focus=near_focus)
            candidates = [found]
            if not found.any() or mask_iou(found, prediction) < settings.follow_iou:
                # moved off its prediction, or out of the window (where the network loses
                # what the window cuts): look again around both, or wider
                anchor = found if found.any() else prediction
                both = found | prediction
                wider = 1.0 if found.any() else settings.search_growth
                candidates.append(self.masked_in(
                    frame_rgb, *self._around(frame_rgb, both, wider), anchor, near=False,
                    focus=None if focus_px is None else dilate(both, focus_px)))
            animals = [c for c in candidates if self._is_animal(frame_rgb, c, state)]
            if animals:  # the one whose area is closest to the animal's
                mask = min(animals, key=lambda c: abs(np.log(np.count_nonzero(c)
                                                             / state.area_px)))
            elif state.mask is not None:  # tracked until now: try its colours
                by_colour = colour_follow(frame_rgb, prediction, state.animal, state.water,
                                          COLOUR_SETTINGS)
                if self._is_animal(frame_rgb, by_colour, state):
                    mask = by_colour
        if mask is None:
            state.mask = None
            state.lost_steps += 1
            return None
        state.moving = state.mask is not None
        state.velocity_px = (centroid(mask) - centroid(state.mask) if state.moving
                             else np.zeros(2))
        state.area_px = ((1 - settings.model_rate) * state.area_px
                         + settings.model_rate * float(np.count_nonzero(mask)))
        state.mask = state.last_seen = mask
        state.animal, state.water = models_near(frame_rgb, mask)
        state.lost_steps = 0
        return mask

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
