"""Animals followed across the scan's sampled frames: each sighting joins the track whose
animal could have swum to it since it was last seen, or starts a new one, so that each
animal of a clip gets one number.

A track reaches as far as its animal is long (the animal may turn about its middle) plus the
distance it could swim at ``MAX_SPEED_M_S`` since its last sighting, from where its last two
sightings say it is heading. Sightings are matched to tracks, each to one, as many as reach
and then with the least distance summed over the matches (``linear_sum_assignment``):
matching the nearest first swapped a touching pair 60 px apart swimming 100 px a sample,
as the nearer of the other's next two sightings was its own. A track not seen for ``MAX_UNSEEN_S`` is closed: an animal that comes back after a
long dive gets a new number (the scan cannot tell two animals apart by their looks).
"""

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import linear_sum_assignment

from dolphinfit.core.scan.sighting import Sighting

MAX_SPEED_M_S = 8.0      # a dolphin's burst speed; cruising is 1–3 m/s
ASSUMED_LENGTH_M = 2.5   # the animal's length where the camera or altitude is unknown
MAX_UNSEEN_S = 8.0       # a track not seen for longer is closed


@dataclass
class Track:
    """One animal's sightings, in frame order."""

    sightings: list[Sighting] = field(default_factory=list)

    @property
    def last(self) -> Sighting:
        """The latest sighting."""
        return self.sightings[-1]

    def is_open(self, frame_idx: int, fps: float) -> bool:
        """Whether the animal may still be matched in ``frame_idx`` (seen within
        ``MAX_UNSEEN_S``)."""
        return (frame_idx - self.last.frame_idx) / fps <= MAX_UNSEEN_S

    def length_px(self) -> float:
        """The animal's typical length, px (the median of its sightings')."""
        return float(np.median([s.length_px for s in self.sightings]))

    def predicted_px(self, frame_idx: int) -> np.ndarray:
        """Where the animal should be in ``frame_idx``: on from its last sighting at the
        speed of its last two."""
        last = np.asarray(self.last.centre_px)
        if len(self.sightings) < 2:
            return last
        before = self.sightings[-2]
        velocity = (last - np.asarray(before.centre_px)) / (self.last.frame_idx
                                                            - before.frame_idx)
        return last + velocity * (frame_idx - self.last.frame_idx)

    def reach_px(self, frame_idx: int, fps: float, px_per_m: float | None) -> float:
        """How far from the prediction a sighting in ``frame_idx`` may lie (module doc)."""
        length = self.length_px()
        scale = px_per_m if px_per_m is not None else length / ASSUMED_LENGTH_M
        seconds = (frame_idx - self.last.frame_idx) / fps
        return length + MAX_SPEED_M_S * seconds * scale


class Tracker:
    """The tracks of one clip, fed the sightings of each sample in frame order."""

    def __init__(self, fps: float) -> None:
        self.fps = fps
        self.tracks: list[Track] = []

    def open_tracks(self, frame_idx: int) -> list[Track]:
        """The tracks that may still be matched in ``frame_idx``."""
        return [track for track in self.tracks if track.is_open(frame_idx, self.fps)]

    def add(self, frame_idx: int, sightings: list[Sighting],
            px_per_m: float | None = None) -> None:
        """Match one sample's sightings to the open tracks (module doc) and start a track
        for each one left over."""
        tracks = self.open_tracks(frame_idx)
        distance = np.zeros((len(tracks), len(sightings)))
        for t, track in enumerate(tracks):
            predicted = track.predicted_px(frame_idx)
            distance[t] = [np.linalg.norm(np.asarray(s.centre_px) - predicted) for s in sightings]
        reach = np.array([track.reach_px(frame_idx, self.fps, px_per_m) for track in tracks])
        reaches = distance <= reach.reshape(-1, 1)
        # beyond reach costs more than every match within reach together: most matches first
        beyond = 1.0 + distance[reaches].sum()
        rows, cols = linear_sum_assignment(np.where(reaches, distance, beyond))
        matched_sightings: set[int] = set()
        for t, i in zip(rows, cols):
            if reaches[t, i]:
                tracks[t].sightings.append(sightings[i])
                matched_sightings.add(i)
        for i, s in enumerate(sightings):
            if i not in matched_sightings:
                self.tracks.append(Track([s]))
