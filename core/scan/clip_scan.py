"""A clip's scan as data: every animal found in it, each sampled frame scored for measuring
it (``frame_scores``), and what the scan knows of the camera (``scan_telemetry``). The scan
itself is ``scanner``'s; this module needs no network, so the app can read and show scans
without loading torch."""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.io.frame_source import Clip
from dolphinfit.core.io.srt import gimbal_pitch_at, parse_srt
from dolphinfit.core.io.telemetry import Telemetry
from dolphinfit.core.scan.frame_scores import FrameScore, ScanSettings, best_frames


@dataclass(frozen=True)
class ClipScan:
    """A clip's scan: the clip (file name, frame rate, frame count, size), the frames
    sampled, the settings, every animal's frame scores (animal by animal, in frame order) and
    the seconds it took."""

    clip_name: str
    fps: float
    num_frames: int
    width_px: int
    height_px: int
    sampled_frames: tuple[int, ...]
    settings: ScanSettings
    scores: tuple[FrameScore, ...]
    seconds: float

    def animal_ids(self) -> list[int]:
        """The animals found, in the order they first showed."""
        return list(dict.fromkeys(score.animal_id for score in self.scores))

    def of_animal(self, animal_id: int) -> list[FrameScore]:
        """One animal's scores, in frame order."""
        return [score for score in self.scores if score.animal_id == animal_id]

    def best(self, animal_id: int, count: int | None = None) -> list[FrameScore]:
        """An animal's best usable frames, best first (``settings.best_count`` of them by
        default)."""
        return best_frames(self.of_animal(animal_id),
                           self.settings.best_count if count is None else count)


@dataclass(frozen=True)
class ClipTelemetry:
    """What the scan knows of the camera: its focal length in pixels and, per frame of the
    clip, the altitude (m) and the gimbal's pitch (degrees); NaN where unknown."""

    focal_px: float | None
    altitude_m: np.ndarray
    gimbal_pitch_deg: np.ndarray


def scan_telemetry(clip: Clip, telemetry: Telemetry | None,
                   focal_px: float | None) -> ClipTelemetry:
    """What a scan knows of ``clip``'s camera: the altitude per frame (NaN without
    ``telemetry``), the focal length in pixels, and the gimbal's pitch where the SRT the
    altitude came from records it."""
    if telemetry is None:
        nothing = np.full(clip.num_frames, np.nan)
        return ClipTelemetry(focal_px, nothing, nothing)
    times = clip.frame_time_s(np.arange(clip.num_frames))
    pitch = gimbal_pitch_at(parse_srt(telemetry.source.path), times) \
        if telemetry.source.kind == "srt" else np.full(clip.num_frames, np.nan)
    return ClipTelemetry(focal_px, telemetry.altitude_m, pitch)
