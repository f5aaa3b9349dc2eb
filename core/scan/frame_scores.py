"""How measurable each sampled frame is for each animal: the sighting's measures made
relative to the animal's own best, the frame's hard faults, and one quality to rank by.

Relative, because what a sharp frame or a long body is depends on the clip (its resolution,
water and light) and the animal: each measure is divided by the 90th percentile of that
animal's sightings (``REFERENCE_PERCENTILE``: its best frames, robust to one glint) and capped
at 1. The quality is the product

    length share × straightness × √(sharpness share) × contrast share

(the square root because the Laplacian's variance grows with the square of the edge's
steepness). A frame is **usable** when it has none of these faults, each the reason a
person would put it aside:

- the animal is within ``EDGE_MARGIN_PX`` of the frame's edge (it may be cut off);
- it is shorter than ``MIN_LENGTH_SHARE`` of its usual best (pitched, diving or arched:
  its length and widths are foreshortened);
- no altitude, or an altitude outside the range the user set (DESIGN: a measurement needs
  its altitude; a range keeps the GSD within what the altimeter was calibrated for);
- the gimbal more than ``ScanSettings.max_gimbal_off_deg`` from straight down, where the
  SRT records its pitch (an oblique view foreshortens the animal; the field's protocols ask
  for a nadir camera, e.g. Christiansen et al. 2016, Torres et al. 2022).
"""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.scan.sighting import Sighting

REFERENCE_PERCENTILE = 90
EDGE_MARGIN_PX = 5
MIN_LENGTH_SHARE = 0.85
NADIR_PITCH_DEG = -90.0


@dataclass(frozen=True)
class ScanSettings:
    """What the scan samples and accepts: frames per second sampled, seconds between looks
    at the whole frame for animals coming into view and between full searches of it in
    tiles (between them each animal is looked for around where it was), the altitude range
    in metres a frame must lie in (None: any), how far from straight down the gimbal may
    point, and how many best frames per animal are listed."""

    sample_fps: float = 1.0
    search_every_s: float = 5.0
    tile_search_every_s: float = 15.0
    altitude_range_m: tuple[float, float] | None = None
    max_gimbal_off_deg: float = 5.0
    best_count: int = 5


@dataclass(frozen=True)
class FrameScore:
    """One animal in one sampled frame: the sighting's measures (``sighting`` module doc),
    the frame's altitude (m) and gimbal pitch (degrees, −90 straight down; NaN where
    unknown), the shares of the animal's best, the quality, and the faults that make the
    frame unusable (module doc)."""

    animal_id: int
    frame_idx: int
    time_s: float
    centre_x_px: float
    centre_y_px: float
    length_px: float
    length_m: float
    straightness: float
    sharpness: float
    contrast: float
    border_px: float
    altitude_m: float
    gimbal_pitch_deg: float
    length_share: float
    sharpness_share: float
    contrast_share: float
    quality: float
    faults: tuple[str, ...]

    @property
    def is_usable(self) -> bool:
        """Whether no fault puts the frame aside."""
        return not self.faults


def share_of_best(values: np.ndarray) -> np.ndarray:
    """``values`` over their ``REFERENCE_PERCENTILE``-th percentile, capped at 1 (0 where that
    is not positive)."""
    reference = np.percentile(values, REFERENCE_PERCENTILE)
    if not reference > 0:
        return np.zeros_like(values)
    return np.minimum(values / reference, 1.0)


def frame_faults(seen: Sighting, length_share: float, altitude_m: float,
                 gimbal_pitch_deg: float, settings: ScanSettings) -> tuple[str, ...]:
    """The module doc's faults of one sighting, in words."""
    faults = []
    if seen.border_px < EDGE_MARGIN_PX:
        faults.append("at the frame's edge")
    if length_share < MIN_LENGTH_SHARE:
        faults.append(f"{100 * length_share:.0f} % of its length: pitched, diving or arched")
    if not np.isfinite(altitude_m):
        faults.append("no altitude")
    elif settings.altitude_range_m is not None and \
            not settings.altitude_range_m[0] <= altitude_m <= settings.altitude_range_m[1]:
        low, high = settings.altitude_range_m
        faults.append(f"altitude {altitude_m:.1f} m outside {low:g}–{high:g} m")
    if np.isfinite(gimbal_pitch_deg) and \
            abs(gimbal_pitch_deg - NADIR_PITCH_DEG) > settings.max_gimbal_off_deg:
        faults.append(f"gimbal pitch {gimbal_pitch_deg:.0f}°")
    return tuple(faults)


def track_scores(animal_id: int, seen: list[Sighting], fps: float, altitude_m: np.ndarray,
                 gimbal_pitch_deg: np.ndarray, focal_px: float | None,
                 settings: ScanSettings) -> list[FrameScore]:
    """The scores of one animal's sightings (module doc), under its number. ``altitude_m``
    and ``gimbal_pitch_deg``: per frame of the clip, NaN where unknown."""
    lengths = share_of_best(np.array([s.length_px for s in seen]))
    sharpness = share_of_best(np.array([s.sharpness for s in seen]))
    contrast = share_of_best(np.array([s.contrast for s in seen]))
    scores = []
    for s, length_share, sharp_share, contrast_share in zip(seen, lengths, sharpness, contrast,
                                                              strict=True):
        altitude = float(altitude_m[s.frame_idx])
        pitch = float(gimbal_pitch_deg[s.frame_idx])
        metres = s.length_px * altitude / focal_px if focal_px is not None else float("nan")
        scores.append(FrameScore(
            animal_id=animal_id, frame_idx=s.frame_idx, time_s=s.frame_idx / fps,
            centre_x_px=s.centre_px[0], centre_y_px=s.centre_px[1], length_px=s.length_px,
            length_m=metres, straightness=s.straightness, sharpness=s.sharpness,
            contrast=s.contrast, border_px=s.border_px, altitude_m=altitude,
            gimbal_pitch_deg=pitch, length_share=float(length_share),
            sharpness_share=float(sharp_share), contrast_share=float(contrast_share),
            quality=float(length_share * s.straightness * np.sqrt(sharp_share)
                          * contrast_share),
            faults=frame_faults(s, float(length_share), altitude, pitch, settings)))
    return scores


def best_frames(scores: list[FrameScore], count: int) -> list[FrameScore]:
    """The ``count`` usable frames of highest quality, best first."""
    usable = [score for score in scores if score.is_usable]
    return sorted(usable, key=lambda score: -score.quality)[:count]
