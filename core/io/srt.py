"""DJI .SRT telemetry sidecars, every family of reference/ecosystem.md §7.

A file is a sequence of subtitle cues: a number line, usually a timing line
(``00:00:01,000 --> 00:00:02,000``; some files have none), then payload lines up to a blank
line. The payload's layout depends on the drone family:

- **modern** (Mavic 3, Mini 3/4 Pro, Air 3S, Neo), per frame: ``FrameCnt: 1, DiffTime: 20ms``
  / date / ``[iso: 220] … [rel_alt: -2.400 abs_alt: 0.401]``. Altitude: ``rel_alt``, relative.
- **html-bracket** (Mavic 2, Air 2, Air 2S), per frame: ``SrtCnt : 1, DiffTime : 16ms`` / date
  / ``[iso : 100] … [altitude: 27.300000]``. Altitude: ``altitude``, absolute. A Mavic 2 Pro
  variant has no timing lines and no altitude at all.
- **single-line** (Mavic Mini/Mini 2, Phantom 4 Pro, P4 RTK), 1 Hz: ``F/2.8, SS 30.15, ISO 260,
  EV -1.7, GPS (…), D 221.21m, H 200.70m, H.S …, V.S …``. Altitude: ``H``, relative.
- **m300** (Matrice 300), 1 Hz: date / ``GPS(lat,lon,0.0M) BAROMETER:0.3M``. Altitude:
  ``BAROMETER``, relative.
- **legacy** (Mavic Pro, early Phantom/Inspire), 1 Hz: ``HOME(lon,lat) date`` /
  ``GPS(lon,lat,n) BAROMETER:1.9`` / ``ISO:… Shutter:… EV:… Fnum:…``; an older variant writes
  ``Hb:`` and ``Hs:``. Altitude: ``BAROMETER`` or ``Hb``, relative.

Relative altitudes are barometric heights above the take-off point: the reader adds the
take-off point's height above the water (``launch_height_m``). Absolute altitudes are above
sea level and are used as they are. ``focal_len`` is a 35 mm-equivalent value (×10 in the
html-bracket family) and is dropped on reading: it never gives scale (DESIGN.md §3). Date
lines are the camera's local time, without a timezone (``srt_clock_start``: the date-time at
the video's 0 s); the single-line family has none.

Tolerated quirks: ``key : value`` spacing that varies inside a cue, two keys in one bracket,
``longtitude``, negative ``rel_alt``, a ``60`` in a timing line's seconds (Matrice 300), date
lines with extra sub-second groups, counters that do not start at 1, blank-line runs, and
truncated or empty cues at the end (warnings, not errors). DJI FPV files (altitude ÷10) are
not recognised: no sample file was available to identify them.
"""

import re
from dataclasses import dataclass
from datetime import datetime, timedelta
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_samples import AltitudeSamples, AltitudeSource
from dolphinfit.core.io.report import list_some
from dolphinfit.core.io.text_input import read_text


@dataclass(frozen=True)
class SrtFamily:
    """A DJI SRT family: the drones that write it and which field holds the altitude."""

    name: str
    models: str
    altitude_fields: tuple[str, ...]  # candidates, the first one present in the file is used
    is_relative: bool  # height above the take-off point (launch height to be added)


FAMILIES = {family.name: family for family in (
    SrtFamily("modern", "Mavic 3, Mini 3/4 Pro, Air 3S, Neo, Mini 5 Pro", ("rel_alt",), True),
    SrtFamily("html-bracket", "Mavic 2, Air 2, Air 2S", ("altitude",), False),
    SrtFamily("single-line", "Mavic Mini/Mini 2, Phantom 4 Pro, P4 RTK", ("H",), True),
    SrtFamily("m300", "Matrice 300", ("BAROMETER",), True),
    SrtFamily("legacy", "Mavic Pro, early Phantom/Inspire", ("BAROMETER", "Hb"), True),
)}

# Family signatures, tried in this order on each cue's payload until one matches: the modern
# family also has brackets, and the legacy family also has BAROMETER.
_SIGNATURES = (
    ("modern", re.compile(r"FrameCnt|rel_alt")),
    ("html-bracket", re.compile(r"SrtCnt|\[\s*[A-Za-z_]+\s*:")),
    ("single-line", re.compile(r"(?:^|,)\s*H\s+-?\d+(?:\.\d+)?m")),
    ("legacy", re.compile(r"HOME\(|\bHb\s*:")),
    ("m300", re.compile(r"BAROMETER\s*:")),
)
_NUMBER = r"-?\d+(?:\.\d+)?"
_KEY_COLON_VALUE = re.compile(rf"([A-Za-z_]+)\s*:\s*({_NUMBER})")  # "[iso : 100]", "Hb:12.3"
_KEY_SPACE_VALUE = re.compile(rf"(?:^|,)\s*([A-Za-z][A-Za-z.]*)\s+({_NUMBER})")  # ", H 45.60m"
_TIMING = re.compile(r"^(\d+):(\d+):(\d+)[,.](\d+)\s*-->\s*(\d+):(\d+):(\d+)[,.](\d+)$")
_DATE = re.compile(r"(\d{4})[-.](\d{1,2})[-.](\d{1,2})\s+(\d{1,2}):(\d{2}):(\d{2})"
                   r"(?:[.,](\d{1,3}))?")
_TAG = re.compile(r"<[^>]*>")
DROPPED_FIELDS = frozenset({"focal_len"})  # 35 mm-equivalent: never a focal length (DESIGN §3)


@dataclass(frozen=True)
class SrtCue:
    """One cue: its number, the line it starts on, its timing (seconds on the video clock, None
    without a timing line), its date line (local time, no timezone) and its numeric fields."""

    number: int
    line_no: int
    start_s: float | None
    end_s: float | None
    timestamp: datetime | None
    fields: dict[str, float]
    text: str


@dataclass(frozen=True)
class SrtFile:
    """A parsed SRT file: its family, its cues in file order, and reading warnings."""

    path: Path
    family: SrtFamily
    cues: tuple[SrtCue, ...]
    warnings: tuple[str, ...]


def _timing_s(match: re.Match) -> tuple[float, float]:
    """(start_s, end_s) of a timing line; fields are not range-checked (60 s occurs)."""
    values = [int(g) for g in match.groups()]
    start_ms, end_ms = (len(match.group(4)), len(match.group(8)))
    start = values[0] * 3600 + values[1] * 60 + values[2] + values[3] / 10**start_ms
    end = values[4] * 3600 + values[5] * 60 + values[6] + values[7] / 10**end_ms
    return start, end


def _timestamp(text: str) -> datetime | None:
    """The first date-time in ``text`` (extra sub-second groups ignored), or None."""
    match = _DATE.search(text)
    if match is None:
        return None
    year, month, day, hour, minute, second = (int(g) for g in match.groups()[:6])
    millis = match.group(7) or "0"
    try:
        return datetime(year, month, day, hour, minute, second,
                        int(millis) * 10 ** (6 - len(millis)))
    except ValueError:
        return None


def _fields(text: str) -> dict[str, float]:
    """Numeric ``key: value`` and single-line ``KEY value`` fields of a cue's payload."""
    fields = {key: float(value) for key, value in _KEY_SPACE_VALUE.findall(text)}
    fields.update((key, float(value)) for key, value in _KEY_COLON_VALUE.findall(text))
    return {key: value for key, value in fields.items() if key not in DROPPED_FIELDS}


def _cue(number: int, line_no: int, lines: list[str]) -> SrtCue:
    """A cue from its number, first line number and the lines after the number line."""
    timing = _TIMING.match(lines[0].strip()) if lines else None
    start_s, end_s = _timing_s(timing) if timing else (None, None)
    text = _TAG.sub("", "\n".join(lines[1:] if timing else lines))
    return SrtCue(number, line_no, start_s, end_s, _timestamp(text), _fields(text), text)


def _parse_cues(text: str) -> list[SrtCue]:
    """Split SRT text into cues: a bare number after a blank line (or at the top) starts one,
    a blank line ends its payload."""
    lines = text.splitlines()
    cues = []
    line_idx = 0
    while line_idx < len(lines):
        stripped = lines[line_idx].strip()
        is_start = stripped.isdigit() and (line_idx == 0 or not lines[line_idx - 1].strip())
        if not is_start:
            line_idx += 1
            continue
        body_start = line_idx + 1
        body_end = body_start
        while body_end < len(lines) and lines[body_end].strip():
            body_end += 1
        cues.append(_cue(int(stripped), line_idx + 1, lines[body_start:body_end]))
        line_idx = body_end
    return cues


def _detect_family(path: Path, cues: list[SrtCue]) -> SrtFamily:
    """The family of the first cue whose payload carries a known signature."""
    for cue in cues:
        for name, signature in _SIGNATURES:
            if signature.search(cue.text):
                return FAMILIES[name]
    raise InputError(f"{path}: {len(cues)} cues but none carries DJI telemetry "
                     "(not a DJI SRT file?)")


def _cue_list(cues: list[SrtCue]) -> str:
    """"cue 20 (line 96), …" for the first few cues."""
    return list_some([f"cue {c.number} (line {c.line_no})" for c in cues])


def _is_empty(cue: SrtCue) -> bool:
    """A cue with a number and nothing else (files cut off mid-write end with these)."""
    return cue.start_s is None and not cue.text.strip()


def parse_srt(path: Path | str) -> SrtFile:
    """Read a DJI SRT file; InputError if it holds no cue with DJI telemetry.

    Empty cues are dropped with a warning naming them.
    """
    path = Path(path)
    text = read_text(path)
    if not text.strip():
        raise InputError(f"{path}: the file is empty")
    cues = _parse_cues(text)
    if not cues:
        raise InputError(f"{path}: no subtitle cues found (not an SRT file)")
    empty = [c for c in cues if _is_empty(c)]
    warnings = [f"{path}: empty {_cue_list(empty)} dropped"] if empty else []
    cues = [c for c in cues if not _is_empty(c)]
    return SrtFile(path, _detect_family(path, cues), tuple(cues), tuple(warnings))


def _cue_times_s(srt: SrtFile) -> tuple[np.ndarray, list[str]]:
    """(N,) cue times on the video clock (NaN where unknown) and the warnings about them.

    Timing lines give the times. A file without any (one cue a second, but date lines that
    skip and repeat seconds) places cue n at (n − first cue number) × the median spacing of its
    date lines.
    """
    if any(c.start_s is not None for c in srt.cues):
        times = np.array([np.nan if c.start_s is None else c.start_s for c in srt.cues])
        untimed = [c for c in srt.cues if c.start_s is None]
        warnings = [f"{srt.path}: no timing line in {_cue_list(untimed)}"] if untimed else []
        return times, warnings
    dated = [c for c in srt.cues if c.timestamp is not None]
    spacing_s = np.median([(b.timestamp - a.timestamp).total_seconds() / (b.number - a.number)
                           for a, b in zip(dated, dated[1:]) if b.number > a.number] or [np.nan])
    if not spacing_s > 0:
        raise InputError(f"{srt.path}: no timing lines and too few dated cues: times are unknown")
    first = srt.cues[0].number
    times = np.array([(c.number - first) * spacing_s for c in srt.cues])
    return times, [f"{srt.path}: no timing lines; cues taken {spacing_s:g} s apart (the median "
                   "spacing of their date lines)"]


def srt_clock_start(srt: SrtFile) -> datetime | None:
    """The camera's local date-time (no timezone) at the video's time 0: the median over the
    dated cues of date line − cue time, which evens out date lines that skip or repeat a
    second; None when no cue carries a date (the single-line family). InputError as
    ``_cue_times_s`` when cue times are unknown."""
    if all(c.timestamp is None for c in srt.cues):
        return None
    times, _ = _cue_times_s(srt)
    dated = [(c.timestamp, t) for c, t in zip(srt.cues, times)
             if c.timestamp is not None and np.isfinite(t)]
    if not dated:
        return None
    first = dated[0][0]
    offsets_s = [(stamp - first).total_seconds() - t for stamp, t in dated]
    return first + timedelta(seconds=float(np.median(offsets_s)))


def _altitude_field(srt: SrtFile) -> str:
    """The first of the family's altitude fields that any cue carries, or ""."""
    for field in srt.family.altitude_fields:
        if any(field in c.fields for c in srt.cues):
            return field
    return ""


def _increasing(times: np.ndarray) -> np.ndarray:
    """(N,) bool: the times that are known and later than every known time before them."""
    keep = np.isfinite(times)
    keep[keep] = np.concatenate([[True], np.diff(np.maximum.accumulate(times[keep])) > 0])
    return keep


def _altitude_warnings(srt: SrtFile, field: str, launch_height_m: float) -> list[str]:
    """Warnings about cues without the altitude field and a missing launch height."""
    family = srt.family
    if not field:
        return [f"{srt.path}: no cue carries an altitude ({family.name} family, looked for "
                f"{' or '.join(family.altitude_fields)}): give the altitude another way"]
    warnings = []
    lacking = [c for c in srt.cues if field not in c.fields]
    if lacking:
        warnings.append(f"{srt.path}: no {field} in {_cue_list(lacking)} (truncated?)")
    if family.is_relative and launch_height_m == 0.0:
        warnings.append(f"{srt.path}: {field} is height above the take-off point and no launch "
                        "height was given (the take-off point's height above the water)")
    return warnings


def srt_altitude(srt: SrtFile, launch_height_m: float = 0.0) -> AltitudeSamples:
    """Altitude samples of a parsed SRT: one per cue with a time, metres above the water.

    Relative fields get ``launch_height_m`` added. Cues without the altitude field (truncated
    cues) give NaN samples; cues without a time, or not later than the cue before, are dropped;
    each case adds a warning naming the cues.
    """
    family, field = srt.family, _altitude_field(srt)
    times, time_warnings = _cue_times_s(srt)
    warnings = [*srt.warnings, *time_warnings, *_altitude_warnings(srt, field, launch_height_m)]
    offset_m = launch_height_m if family.is_relative else 0.0
    altitude = np.array([c.fields.get(field, np.nan) + offset_m for c in srt.cues])
    keep = _increasing(times)
    out_of_order = [c for c, k, t in zip(srt.cues, keep, times) if not k and np.isfinite(t)]
    if out_of_order:
        warnings.append(f"{srt.path}: {_cue_list(out_of_order)} not later than the cue before: "
                        "dropped")
    if not keep.any():
        raise InputError(f"{srt.path}: no cue has a usable time")
    source = AltitudeSource("srt", srt.path, family.name, field, family.is_relative, offset_m)
    return AltitudeSamples(altitude[keep], source, time_s=times[keep], warnings=tuple(warnings))


def read_srt(path: Path | str, launch_height_m: float = 0.0) -> AltitudeSamples:
    """Altitude samples of a DJI SRT file (``parse_srt`` then ``srt_altitude``)."""
    return srt_altitude(parse_srt(path), launch_height_m)


GIMBAL_PITCH_FIELDS = ("gb_pitch", "gimbal_pitch", "GimbalPitch")  # as DJI firmwares name it


def gimbal_pitch_at(srt: SrtFile, times_s: np.ndarray) -> np.ndarray:
    """The gimbal's pitch (degrees, −90 straight down) at ``times_s`` on the video clock, from
    the latest cue at or before each time that records it; NaN where none does (most SRT
    families do not)."""
    field = next((name for name in GIMBAL_PITCH_FIELDS
                  if any(name in c.fields for c in srt.cues)), None)
    pitch = np.full(np.shape(times_s), np.nan)
    if field is None:
        return pitch
    times, _ = _cue_times_s(srt)
    known = [(t, c.fields[field]) for t, c in zip(times, srt.cues)
             if np.isfinite(t) and field in c.fields]
    cue_times = np.array([t for t, _ in known])
    values = np.array([value for _, value in known])
    order = np.argsort(cue_times, kind="stable")
    at = np.searchsorted(cue_times[order], times_s, side="right") - 1
    has_cue = at >= 0
    pitch[has_cue] = values[order][at[has_cue]]
    return pitch
