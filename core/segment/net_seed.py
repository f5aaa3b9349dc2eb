"""The network tracker's seed: the animal's mask in the seed frame from a click, a box or
by itself, at the working scale.

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

import cv2
import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.progress import check_cancel
from dolphinfit.core.segment.auto_seed import (
    Candidate, cut_by_window, find_animals, is_animal_shaped, is_lone, scan_order,
)
from dolphinfit.core.segment.bodies import dolphin_unlikeness, own_body
from dolphinfit.core.segment.net_look import NetLook
from dolphinfit.core.segment.seed import POINT_SEARCH_FRACTION, dilate, seed_mask, shape_of
from dolphinfit.core.segment.segmenter import AutoSeed, BoxSeed, Frames, PointSeed, Seed
from dolphinfit.core.segment.windows import MIN_WINDOW_PX, longer_side, square_window
from dolphinfit.core.segment.working_scale import downscaled, resized, scaled_seed, scaled_size

KEPT_SHARE = 0.85          # the automatic seed's redraw keeps this much of what it found
AUTO_SEED_FRAMES = 12      # frames the automatic seed looks at before it gives up
WHOLE_SHARE = 0.8          # the whole frame's component must hold this much of a click's pick
SCALE_ROUNDS = 3           # looks at a large animal, each at the scale the last one asked for
SCALE_MARGIN = 0.9         # the working scale leaves the animal this much under the limit


class NetSeeder:
    """The seed's looks, with the tracker's ``look`` (module doc)."""

    def __init__(self, look: NetLook) -> None:
        self.look = look

    def scan(self, frames: Frames, seed: AutoSeed, chosen: Sequence[int],
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

    def at_working_scale(self, frame_rgb: np.ndarray, seed: Seed,
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
            mask = self.seed_mask(seen, seed if scale == 1.0 else scaled_seed(seed, scale),
                                  first if scale == 1.0 else None if found is None
                                  else downscaled(found, seen.shape[:2]))
            if longer_side(mask) <= self.look.settings.max_length_px:
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
        if length <= self.look.settings.max_length_px:
            return 1.0
        return SCALE_MARGIN * self.look.settings.max_length_px / length

    def seed_mask(self, frame_rgb: np.ndarray, seed: Seed,
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
            side = max(MIN_WINDOW_PX, self.look.settings.first_window_fraction * min(height, width))
            rows, cols = square_window(np.array([seed.x_px, seed.y_px]), side, height, width)
            mask, (rows, cols) = self._clicked(frame_rgb, rows, cols, seed, found)
        elif isinstance(seed, BoxSeed):
            box = np.zeros((height, width), bool)
            box[seed.y_px:seed.y_px + seed.height_px, seed.x_px:seed.x_px + seed.width_px] = True
            rows, cols = self.look.around(frame_rgb, box)
            mask = self.look.masked_in(frame_rgb, rows, cols, box) & \
                dilate(box, self.look.settings.min_near_px)
        else:  # the tile shows the animal small: look again in a window around what it found
            animals = [] if found is not None else self._animals(frame_rgb, seed)
            mask = found if found is not None else (
                animals[0].mask if animals else np.zeros(frame_rgb.shape[:2], bool))
            rows, cols = self.look.around(frame_rgb, mask) if mask.any() else (slice(0), slice(0))
            again = self.look.masked_in(frame_rgb, rows, cols, mask, near=False)
            if np.count_nonzero(again & mask) >= KEPT_SHARE * np.count_nonzero(mask):
                mask = again   # a redraw that lost part of the animal is not taken
        growth = 1.0
        for _ in range(self.look.settings.seed_rounds):
            if not mask.any():
                break
            cut_off = cut_by_window(mask, rows, cols)
            if cut_off:
                growth *= self.look.settings.search_growth
            rows, cols = self.look.around(frame_rgb, mask, growth)
            again = self.look.masked_in(frame_rgb, rows, cols, mask, near=False)
            if isinstance(seed, BoxSeed):
                again &= dilate(box, self.look.settings.min_near_px)
            if not again.any():
                growth *= self.look.settings.search_growth  # the window may hold only the animal
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
        return find_animals(frame_rgb, self.look.net.saliency, self.look.settings.tile_fraction,
                            self.look.settings.threshold, seed.length_px)

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
        saliency = self.look.saliency(crop, clicked)
        count, labels = cv2.connectedComponents(
            (saliency >= self.look.settings.threshold).astype(np.uint8), connectivity=8)
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
