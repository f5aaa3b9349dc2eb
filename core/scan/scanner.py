"""The scan of a clip: every animal in view, followed across sampled frames, and each sampled
frame scored for measuring each animal, so that a person measures the frames worth it.

Frames are sampled at ``ScanSettings.sample_fps``. On the first sample, every
``tile_search_every_s`` after it and whenever no animal is being followed, the whole frame
is searched as the automatic seed searches it (``auto_seed.find_animals``: the salient
network on the frame and on tiles sized by the camera, and the colour detector), which costs
about 3 s at 1080p on two cores; on the samples between, each animal followed is looked for
once around where it should be (``WINDOW_LENGTHS`` of its length across: one look of the
network, about 0.3 s), and every ``search_every_s`` the network looks once at the whole
frame for animals coming into view. Where no animal followed is found around where it should
be, the whole frame is searched again on that sample: a look around a prediction misses an
animal that turned or sped up (a 4-s clip gives the scan only 4 samples). Not where some are
found: a patch of glitter followed for a sample and then gone would have every later sample
searched whole (over white sand with caustics, a search on every miss found 10 "animals"
where the scan finds 6, in four times the time). The sightings join the animals' tracks (``tracks``) and each is scored
(``frame_scores``). An animal must persist: seen in at least ``MIN_SIGHTINGS`` samples (where
the clip has that many) and in at least ``MIN_SEEN_SHARE`` of the samples from its first
sighting to its last, unless it was seen in ``STEADY_SIGHTINGS`` or more keeping its length
(a pair touching, seen in 7 of 14 samples at 154–173 px, was dropped). A splash or a patch of glitter the network takes for an animal is seen
now and then (on the sample clip's glitter: in 2 of 5 samples), an animal in nearly every
sample while it is in view; and glitter changes its shape from sample to sample, an animal
keeps its length: seen fewer than ``STEADY_SIGHTINGS`` times, two of its sightings must agree
within ``MAX_LENGTH_RATIO`` (the sample's glitter: 2.11 m then 1.28 m, 1.65×; its dolphin
1.94–2.15 m; one of a pair at 480 px seen 87, 78, then 40 px long where its neighbour cut
its mask).
"""

import threading
import time
from dataclasses import replace

import numpy as np

from dolphinfit.core.io.frame_source import FrameSource
from dolphinfit.core.io.video import frames_at_fps
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel
from dolphinfit.core.scan.clip_scan import ClipScan, ClipTelemetry
from dolphinfit.core.scan.frame_scores import ScanSettings, track_scores
from dolphinfit.core.scan.sighting import sighting
from dolphinfit.core.scan.tracks import Track, Tracker
from dolphinfit.core.segment.auto_seed import (
    DOLPHIN_LENGTH_M, MIN_TILE_PX, expected_length_px, colour_candidates, find_animals, same_animal, window_candidates,
)
from dolphinfit.core.segment.net_settings import NetSettings
from dolphinfit.core.segment.salient import SalientNet
from dolphinfit.core.segment.windows import square_window

WINDOW_LENGTHS = 3.0   # the look around a followed animal is this many of its length across
MIN_SIGHTINGS = 2      # samples an animal must be seen in (module doc)
MIN_SEEN_SHARE = 0.6   # of the samples from its first sighting to its last (module doc)
STEADY_SIGHTINGS = 4   # fewer sightings than this: two must agree on the length (module doc) …
MAX_LENGTH_RATIO = 1.5  # … the longer at most this much longer than the shorter


class Scanner:
    """The salient network and settings a scan looks with (module doc); one per thread."""

    def __init__(self, net: SalientNet | None = None,
                 settings: NetSettings = NetSettings()) -> None:
        self.net = net if net is not None else SalientNet()
        self.settings = settings

    def scan(self, frames: FrameSource, telemetry: ClipTelemetry,
             settings: ScanSettings = ScanSettings(),
             progress: ProgressCallback | None = None,
             cancel: threading.Event | None = None,
             samples: list[int] | None = None) -> ClipScan:
        """Scan ``frames`` (module doc) at the ``samples`` given (default: the whole clip at
        ``settings.sample_fps``); Cancelled when ``cancel`` is set between samples."""
        started = time.perf_counter()
        clip = frames.clip
        if samples is None:
            samples = [int(t) for t in frames_at_fps(clip, settings.sample_fps)]
        expected = None if telemetry.focal_px is None else expected_length_px(
            telemetry.focal_px, telemetry.altitude_m, DOLPHIN_LENGTH_M)
        tracker, searched_at, glanced_at = Tracker(clip.fps), None, None
        for step, frame_idx in enumerate(samples):
            check_cancel(cancel)
            frame = frames[frame_idx]
            followed = tracker.open_tracks(frame_idx)
            if searched_at is None or not followed or \
                    (frame_idx - searched_at) / clip.fps >= settings.tile_search_every_s:
                masks = self._searched(frame, expected)
                searched_at = glanced_at = frame_idx
            else:
                masks = self._followed(frame, frame_idx, followed, expected)
                if not masks:   # none was where it should be: look again
                    masks = self._searched(frame, expected)
                    searched_at = glanced_at = frame_idx
                elif (frame_idx - glanced_at) / clip.fps >= settings.search_every_s:
                    masks += self._newcomers(frame, masks, expected)
                    glanced_at = frame_idx
            seen = [s for s in (sighting(frame, mask, frame_idx) for mask in masks)
                    if s is not None]
            tracker.add(frame_idx, seen, _px_per_m(telemetry, frame_idx))
            if progress is not None:
                progress(Progress("scan", step + 1, len(samples),
                                  f"frame {frame_idx}: {len(seen)} animal"
                                  f"{'s' if len(seen) != 1 else ''} in view"))
        kept = [t for t in tracker.tracks if persists(t, samples)]
        scores = [score for number, track in enumerate(kept, start=1)   # in order of showing
                  for score in track_scores(number, track.sightings, clip.fps,
                                            telemetry.altitude_m, telemetry.gimbal_pitch_deg,
                                            telemetry.focal_px, settings)]
        return ClipScan(clip.path.name, clip.fps, clip.num_frames, clip.width_px,
                        clip.height_px, tuple(samples), settings, tuple(scores),
                        time.perf_counter() - started)

    def _searched(self, frame: np.ndarray,
                  expected: tuple[float, float] | None) -> list[np.ndarray]:
        """The masks of every animal in the whole frame (``auto_seed.find_animals``)."""
        return [c.mask for c in find_animals(frame, self.net.saliency, self.settings.tile_fraction,
                                             self.settings.threshold, expected)]

    def _newcomers(self, frame: np.ndarray, known: list[np.ndarray],
                   expected: tuple[float, float] | None) -> list[np.ndarray]:
        """Animals come into view: one look of the network at the whole frame, keeping what
        is none of the ``known`` animals."""
        height, width = frame.shape[:2]
        found = window_candidates(frame, slice(0, height), slice(0, width), self.net.saliency,
                                  self.settings.threshold, expected)
        return [c.mask for c in found if not any(same_animal(c.mask, k) for k in known)]

    def _followed(self, frame: np.ndarray, frame_idx: int, followed: list[Track],
                  expected: tuple[float, float] | None) -> list[np.ndarray]:
        """Each followed animal's mask in this frame, looked for around where it should be
        (the network's component nearest there, else the colour detector's); animals not
        found there are left out."""
        height, width = frame.shape[:2]
        taken: list[np.ndarray] = []
        for track in followed:
            centre = track.predicted_px(frame_idx)
            rows, cols = square_window(centre, max(WINDOW_LENGTHS * track.length_px(),
                                                   MIN_TILE_PX), height, width)
            found = window_candidates(frame, rows, cols, self.net.saliency,
                                      self.settings.threshold, expected)
            if not found:
                found = [replace(c, mask=_in_frame(c.mask, rows, cols, (height, width)))
                         for c in colour_candidates(np.ascontiguousarray(frame[rows, cols]),
                                                    expected)]
            found = [c for c in found if not any(same_animal(c.mask, other) for other in taken)]
            if found:
                nearest = min(found, key=lambda c: np.hypot(*np.subtract(c.centre_px(), centre)))
                taken.append(nearest.mask)
        return taken


def persists(track: Track, samples: list[int]) -> bool:
    """Whether an animal was seen often enough, and steadily enough, to be one (module
    doc)."""
    seen = len(track.sightings)
    span = samples.index(track.last.frame_idx) - samples.index(track.sightings[0].frame_idx) + 1
    lengths = sorted(s.length_px for s in track.sightings)
    if seen < min(MIN_SIGHTINGS, len(samples)):
        return False
    if seen < MIN_SEEN_SHARE * span and not _keeps_its_length(lengths):
        return False
    return seen >= STEADY_SIGHTINGS or any(longer <= MAX_LENGTH_RATIO * shorter
                                           for shorter, longer in zip(lengths, lengths[1:]))


def _keeps_its_length(lengths: list[float]) -> bool:
    """Whether ``STEADY_SIGHTINGS`` or more sightings keep one length: the middle half of them
    within ``MAX_LENGTH_RATIO`` (an animal seen in fewer samples than ``MIN_SEEN_SHARE``, a pair
    touching whose network look parts them now and then, is kept where it keeps its length)."""
    return (len(lengths) >= STEADY_SIGHTINGS
            and np.percentile(lengths, 75) <= MAX_LENGTH_RATIO * np.percentile(lengths, 25))


def _px_per_m(telemetry: ClipTelemetry, frame_idx: int) -> float | None:
    """Pixels per metre on the water in ``frame_idx``; None where unknown."""
    altitude = float(telemetry.altitude_m[frame_idx])
    if telemetry.focal_px is None or not altitude > 0:
        return None
    return telemetry.focal_px / altitude


def _in_frame(mask: np.ndarray, rows: slice, cols: slice, shape: tuple[int, int]) -> np.ndarray:
    """A window's mask placed in a frame-sized one."""
    whole = np.zeros(shape, bool)
    whole[rows, cols] = mask
    return whole
