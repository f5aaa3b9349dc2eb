"""Altitude as a source recorded it, before alignment to video frames, and its provenance.

Every reader of an altitude format (``srt.py``, ``altitude_csv.py``, ``laser_log.py``) returns
``AltitudeSamples``; ``telemetry.py`` aligns them to a clip's frames.
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass(frozen=True)
class AltitudeSource:
    """Where altitudes come from; recorded with every result (DESIGN.md §8).

    ``kind``: "constant", "srt", "csv" or "laser". ``family``: the DJI SRT family
    (reference/ecosystem.md §7), "lidarbox" or "freefly-astro" for a laser log, else "". ``field``: the field or
    column read ("rel_alt", "BAROMETER", "Hb", "H", "altitude", "laser_altitude_cm",
    "altitude_m", "Camera Range (m)"). ``is_relative``: the field is height above the take-off point, so
    ``launch_height_m`` (the take-off point's height above the water) was added to it.
    ``time_offset_s``: for a laser log, the log time (seconds after its first row) at which the
    clip's first frame was recorded.
    """

    kind: str
    path: Path | None = None
    family: str = ""
    field: str = ""
    is_relative: bool = False
    launch_height_m: float = 0.0
    time_offset_s: float = 0.0

    def describe(self) -> str:
        """One line, e.g. "srt MAVIC3.srt (modern), rel_alt + launch height 1.50 m"."""
        where = f" {self.path.name}" if self.path is not None else ""
        family = f" ({self.family})" if self.family else ""
        field = f", {self.field}" if self.field else ""
        launch = f" + launch height {self.launch_height_m:.2f} m" if self.is_relative else ""
        offset = f", time offset {self.time_offset_s:g} s" if self.kind == "laser" else ""
        return f"{self.kind}{where}{family}{field}{launch}{offset}"


@dataclass(frozen=True, eq=False)
class AltitudeSamples:
    """Altitude samples of one source, keyed by time or by frame.

    altitude_m: (N,) float64, metres above the water surface (launch height already added to
    relative altitudes), NaN where a sample holds no valid altitude. time_s: (N,) float64,
    increasing, seconds on the clip's clock (0 = its first frame), or None when the samples are
    keyed by frame. frame_idx: (N,) int64, increasing, or None when keyed by time. warnings:
    what the reader skipped or doubted, one line each, naming the file and the line or cue.
    (``eq=False``: arrays have no single truth value, so instances compare by identity.)
    """

    altitude_m: np.ndarray
    source: AltitudeSource
    time_s: np.ndarray | None = None
    frame_idx: np.ndarray | None = None
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        keys = self.time_s if self.frame_idx is None else self.frame_idx
        if (self.time_s is None) == (self.frame_idx is None):
            raise ValueError("altitude samples are keyed by time_s or by frame_idx, not both")
        if keys.shape != self.altitude_m.shape or keys.ndim != 1:
            raise ValueError(f"keys {keys.shape} and altitudes {self.altitude_m.shape} must be "
                             "matching (N,) arrays")

    @property
    def num_samples(self) -> int:
        """N, the number of samples (valid or not)."""
        return self.altitude_m.shape[0]

    def key_s(self, fps: float | None = None) -> np.ndarray:
        """(N,) sample times in seconds; frame-keyed samples need the clip's ``fps``."""
        if self.time_s is not None:
            return self.time_s
        if fps is None:
            raise ValueError("frame-keyed altitude samples need the clip's fps to give times")
        return self.frame_idx / fps
