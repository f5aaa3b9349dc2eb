"""Altitude per video frame from any source: a constant, a CSV, a DJI SRT or a laser log.

The format readers (``srt.py``, ``altitude_csv.py``, ``laser_log.py``, ``astro_log.py``) return
``AltitudeSamples``; this module picks the reader for a file, finds a clip's SRT sidecar (same
stem, beside the clip) and aligns samples to the clip's frames. Frame t is shown at t / fps.

Alignment, per frame:

- within SAMPLE_TIME_TOLERANCE_S of a valid sample: that sample's value, exactly;
- between two valid samples at most ``max_gap_s`` apart: linear interpolation;
- before the first or after the last valid sample by at most one sample interval (the
  median spacing of the samples): the nearest sample. Legacy SRT cues start at 1 s, and the
  last cue holds for its duration;
- otherwise missing (NaN).

Samples outside the plausible altitudes of core.limits (a relative altitude without its launch
height, a corrupt cue) count as missing, with a warning.

Frames that are not at a sample are flagged ``is_interpolated``; missing ones ``is_missing``;
those whose own sample was implausible ``is_impossible`` (they may still be bridged: a fit
leaves them out).
"""

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_csv import read_altitude_csv
from dolphinfit.core.io.altitude_samples import AltitudeSamples, AltitudeSource
from dolphinfit.core.io.astro_log import is_astro_log, read_astro_log
from dolphinfit.core.io.laser_log import is_laser_log, read_laser_log
from dolphinfit.core.io.report import format_runs, list_some
from dolphinfit.core.io.srt import read_srt
from dolphinfit.core.io.video import Clip
from dolphinfit.core.limits import ALTITUDE_M, LAUNCH_HEIGHT_M, in_range, number

SAMPLE_TIME_TOLERANCE_S = 0.0005  # half the 1 ms resolution of SRT timing lines
# Longest stretch without a valid sample that is bridged by interpolation: five rows of a
# 1 Hz laser log; a drone hovering over an animal changes height little in that time.
MAX_GAP_S = 5.0
GAP_REPORT_FACTOR = 1.5  # a spacing above 1.5 × the median between valid samples is a gap
SRT_SUFFIX = ".srt"


@dataclass(frozen=True, eq=False)
class Telemetry:
    """Altitude per frame of a clip, with its source.

    altitude_m: (T,) float64, metres above the water surface, NaN where missing. time_s: (T,)
    float64, frame times (t / fps). is_missing, is_interpolated: (T,) bool. warnings: what the
    reader skipped or doubted and which frames lack altitude. is_impossible: (T,) bool, the
    frames whose own sample was implausible (None: none). (``eq=False``: arrays have no
    single truth value, so instances compare by identity.)
    """

    altitude_m: np.ndarray
    time_s: np.ndarray
    is_missing: np.ndarray
    is_interpolated: np.ndarray
    source: AltitudeSource
    warnings: tuple[str, ...] = ()
    is_impossible: np.ndarray | None = None

    @property
    def num_frames(self) -> int:
        """T, the number of frames."""
        return self.altitude_m.shape[0]


@dataclass(frozen=True)
class SamplesSummary:
    """Figures of a sample series: counts, time span (s), rate (Hz), altitude range (m) and
    the gaps between valid samples as (start_s, length_s)."""

    num_samples: int
    num_valid: int
    start_s: float
    end_s: float
    rate_hz: float
    min_altitude_m: float
    max_altitude_m: float
    gaps: tuple[tuple[float, float], ...]


def _number(text: str) -> float | None:
    """``text`` as a float, or None if it is not a number."""
    try:
        return float(text)
    except ValueError:
        return None


def constant_telemetry(altitude_m: float, clip: Clip) -> Telemetry:
    """The same altitude for every frame of ``clip``; InputError unless plausible
    (core.limits.ALTITUDE_M)."""
    altitude_m = in_range(altitude_m, ALTITUDE_M, "altitude")
    num_frames = clip.num_frames
    return Telemetry(np.full(num_frames, float(altitude_m)),
                     clip.frame_time_s(np.arange(num_frames)), np.zeros(num_frames, bool),
                     np.zeros(num_frames, bool), AltitudeSource("constant"))


# The reader for each suffix; a LidarBoX log and a Freefly Astro log are recognised by their
# headers whatever their suffix (the LidarBoX logger names its files LOG_0000.CSV).
READER_KINDS = {SRT_SUFFIX: "srt", ".csv": "csv", ".txt": "laser", ".tsv": "laser",
                ".log": "laser"}


def altitude_file_kind(path: Path) -> str | None:
    """Which reader an existing altitude file needs: "astro", "laser" (by their headers),
    "srt" or "csv" (by the suffix); None when none does."""
    return ("astro" if is_astro_log(path) else "laser" if is_laser_log(path)
            else READER_KINDS.get(path.suffix.lower()))


def read_altitude(path: Path | str, launch_height_m: float = 0.0,
                  time_offset_s: float = 0.0) -> AltitudeSamples:
    """Altitude samples of a DJI SRT, an altitude CSV or a laser log, chosen by the file.

    ``launch_height_m`` is added to relative SRT altitudes; ``time_offset_s`` aligns a laser
    log (see laser_log.py). Either one given where it does not apply adds a warning.
    """
    path = Path(path)
    in_range(launch_height_m, LAUNCH_HEIGHT_M, "launch height")
    number(time_offset_s, "time offset")
    if not path.is_file():
        raise InputError(f"{path}: no such file")
    kind = altitude_file_kind(path)
    if kind == "astro":
        samples = read_astro_log(path, time_offset_s)
    elif kind == "srt":
        samples = read_srt(path, launch_height_m)
    elif kind == "laser":
        samples = read_laser_log(path, time_offset_s)
    elif kind == "csv":
        samples = read_altitude_csv(path)
    else:
        raise InputError(f"{path}: unknown altitude file type {path.suffix!r} (use a DJI .SRT, "
                         "a frame,altitude_m or time_s,altitude_m .csv, a LidarBoX log or a "
                         "Freefly Astro log)")
    ignored = []
    if launch_height_m != 0.0 and not samples.source.is_relative:
        ignored.append(f"launch height ignored: {samples.source.field or 'the altitude'} is "
                       "not relative to the take-off point")
    if time_offset_s != 0.0 and samples.source.kind != "laser":
        ignored.append("time offset ignored: it applies to laser logs only")
    return replace(samples, warnings=samples.warnings + tuple(f"{path}: {w}" for w in ignored))


def _implausible(samples: AltitudeSamples) -> np.ndarray:
    """Which samples hold an altitude outside core.limits.ALTITUDE_M."""
    altitude = samples.altitude_m
    return np.isfinite(altitude) & ((altitude < ALTITUDE_M.low) | (altitude > ALTITUDE_M.high))


def _implausible_as_missing(samples: AltitudeSamples) -> AltitudeSamples:
    """``samples`` with altitudes outside core.limits.ALTITUDE_M made missing (NaN), with a
    warning naming the file, how many and the first few sample times or frames; InputError
    when that leaves no altitude at all."""
    altitude = samples.altitude_m
    valid = np.isfinite(altitude)
    bad = _implausible(samples)
    if not bad.any():
        return samples
    keys = ([f"{t:g} s" for t in samples.time_s[bad]] if samples.frame_idx is None
            else [f"frame {f}" for f in samples.frame_idx[bad]])
    listed = list_some([f"{a:g} m at {key}" for a, key in zip(altitude[bad], keys)])
    hint = " (is the launch height missing?)" if samples.source.is_relative else ""
    where, limits = samples.source.path, ALTITUDE_M.text()
    if not (valid & ~bad).any():
        raise InputError(f"{where}: every altitude lies outside the plausible {limits}: "
                         f"{listed}{hint}")
    warning = (f"{where}: {int(bad.sum())} of {samples.num_samples} altitudes outside the "
               f"plausible {limits} taken as missing: {listed}{hint}")
    return replace(samples, altitude_m=np.where(bad, np.nan, altitude),
                   warnings=samples.warnings + (warning,))


def find_srt_sidecar(clip_path: Path | str) -> Path | None:
    """The .SRT beside a clip with the clip's stem (DJI_0001.MP4 → DJI_0001.SRT), or None."""
    clip_path = Path(clip_path)
    if not clip_path.parent.is_dir():
        return None
    matches = sorted(p for p in clip_path.parent.iterdir()
                     if p.stem == clip_path.stem and p.suffix.lower() == SRT_SUFFIX
                     and p.is_file())
    return matches[0] if matches else None


def align_to_frames(samples: AltitudeSamples, clip: Clip,
                    max_gap_s: float = MAX_GAP_S) -> Telemetry:
    """Altitude per frame of ``clip`` from ``samples`` (rules in the module docstring;
    samples outside core.limits.ALTITUDE_M count as missing)."""
    frame_s = clip.frame_time_s(np.arange(clip.num_frames))
    key_s = samples.key_s(clip.fps)
    is_impossible = _at_any(frame_s, key_s[_implausible(samples)])
    samples = _implausible_as_missing(samples)
    valid = np.isfinite(samples.altitude_m)
    t_valid, a_valid = key_s[valid], samples.altitude_m[valid]
    altitude = np.full(clip.num_frames, np.nan)
    at_sample = np.zeros(clip.num_frames, bool)
    bridged = np.zeros(clip.num_frames, bool)
    if t_valid.size:
        after = np.clip(np.searchsorted(t_valid, frame_s), 0, t_valid.size - 1)
        before = np.clip(after - 1, 0, t_valid.size - 1)
        nearest = np.where(np.abs(frame_s - t_valid[before]) <= np.abs(t_valid[after] - frame_s),
                           before, after)
        at_sample = np.abs(frame_s - t_valid[nearest]) <= SAMPLE_TIME_TOLERANCE_S
        interval_s = float(np.median(np.diff(key_s))) if key_s.size > 1 else 0.0
        inside = (frame_s > t_valid[0]) & (frame_s < t_valid[-1])
        beyond_s = np.maximum(t_valid[0] - frame_s, frame_s - t_valid[-1])
        bridged = ~at_sample & np.where(
            inside, t_valid[after] - t_valid[before] <= max_gap_s + SAMPLE_TIME_TOLERANCE_S,
            beyond_s <= interval_s + SAMPLE_TIME_TOLERANCE_S)
        altitude[bridged] = np.interp(frame_s[bridged], t_valid, a_valid)
        altitude[at_sample] = a_valid[nearest[at_sample]]
    is_missing = ~(at_sample | bridged)
    warnings = samples.warnings
    if is_missing.any():
        warnings += (f"{samples.source.path}: no altitude for {int(is_missing.sum())} of "
                     f"{clip.num_frames} frames of {clip.path.name} "
                     f"(frames {format_runs(is_missing)})",)
    return Telemetry(altitude, frame_s, is_missing, bridged, samples.source, warnings,
                     is_impossible)


def _at_any(frame_s: np.ndarray, times_s: np.ndarray) -> np.ndarray:
    """Whether each frame time lies within SAMPLE_TIME_TOLERANCE_S of one of ``times_s``."""
    if not times_s.size:
        return np.zeros(frame_s.shape, bool)
    times_s = np.sort(times_s)
    after = np.clip(np.searchsorted(times_s, frame_s), 0, times_s.size - 1)
    before = np.clip(after - 1, 0, times_s.size - 1)
    return np.minimum(np.abs(times_s[after] - frame_s),
                      np.abs(frame_s - times_s[before])) <= SAMPLE_TIME_TOLERANCE_S


def load_telemetry(clip: Clip, altitude: str | Path | float | None = None,
                   launch_height_m: float = 0.0, time_offset_s: float = 0.0) -> Telemetry:
    """Altitude per frame of ``clip`` from a number (metres), a file, or, with ``altitude``
    None, the clip's SRT sidecar."""
    if isinstance(altitude, (int, float)):
        return constant_telemetry(float(altitude), clip)
    if isinstance(altitude, str) and _number(altitude) is not None and not Path(altitude).exists():
        return constant_telemetry(float(altitude), clip)
    path = find_srt_sidecar(clip.path) if altitude is None else Path(altitude)
    if path is None:
        raise InputError(f"{clip.path}: no altitude given and no {clip.path.stem}.SRT beside "
                         "the clip")
    return align_to_frames(read_altitude(path, launch_height_m, time_offset_s), clip)


def summarize_samples(samples: AltitudeSamples, fps: float | None = None) -> SamplesSummary:
    """Counts, span, rate, altitude range and gaps of ``samples`` (frame-keyed ones need fps)."""
    key_s = samples.key_s(fps)
    valid = np.isfinite(samples.altitude_m)
    spacing_s = np.diff(key_s)
    interval_s = float(np.median(spacing_s)) if spacing_s.size else np.nan
    t_valid = key_s[valid]
    valid_spacing_s = np.diff(t_valid)
    is_gap = valid_spacing_s > GAP_REPORT_FACTOR * interval_s
    gaps = tuple((float(start), float(length))
                 for start, length in zip(t_valid[:-1][is_gap], valid_spacing_s[is_gap]))
    altitudes = samples.altitude_m[valid]
    return SamplesSummary(
        samples.num_samples, int(valid.sum()), float(key_s[0]), float(key_s[-1]),
        1.0 / interval_s if interval_s > 0 else np.nan,
        float(altitudes.min()) if altitudes.size else np.nan,
        float(altitudes.max()) if altitudes.size else np.nan, gaps)
