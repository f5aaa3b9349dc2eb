"""Read an altitude source, summarise it and optionally write it as CSV.

  dolphinfit telemetry FILE [--launch-height M] [--time-offset S] [--clip CLIP]
                            [--gps-clock UTC FRAME] [--out FILE.csv]

FILE is a DJI .SRT of any family (modern rel_alt/abs_alt, html-bracket altitude, single-line
H, Matrice 300 and legacy BAROMETER or Hb), an altitude CSV (frame,altitude_m or
time_s,altitude_m), a LidarBoX laser log (laser_altitude_cm × cos(tilt_deg)) or a Freefly
Astro flight log (its camera range).
--launch-height adds the take-off point's height above the water to relative altitudes.
--time-offset is the laser-log time (s after its first row) at which the clip starts;
--gps-clock UTC FRAME derives it from a GPS clock filmed in --clip: the clock read UTC
(YYYY/MM/DD HH:MM:SS.s, the log's own time base) at frame FRAME.
--clip also aligns the altitude to the clip's frames (an SRT beside it is its own clock).
--out writes time_s,altitude_m, one row per sample (seconds from the start of the recording,
launch height added); with --clip, frame,time_s,altitude_m,is_interpolated, one row per video
frame (altitude empty where missing).
"""

import argparse
import math
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.altitude_csv import write_altitude_csv
from dolphinfit.core.io.altitude_samples import AltitudeSamples
from dolphinfit.core.io.output_paths import check_output_file
from dolphinfit.core.io.report import format_runs
from dolphinfit.core.io.srt import FAMILIES
from dolphinfit.core.io.telemetry import (
    Telemetry, align_to_frames, read_altitude, summarize_samples,
)
from dolphinfit.core.io.laser_log import gps_clock_offset_s, is_laser_log, parse_clock_time
from dolphinfit.core.io.video import Clip, open_clip
from dolphinfit.core.limits import count
from dolphinfit.app.commands.altitude_options import add_altitude_offsets, check_altitude_offsets

SOURCE_NAMES = {"srt": "DJI SRT", "csv": "altitude CSV", "laser": "laser log"}
LOGGER_NAMES = {"lidarbox": "LidarBoX", "freefly-astro": "Freefly Astro"}  # by source.family


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The file, the launch height, the time offset, the clip and the output."""
    parser.add_argument("file", type=Path, help="a DJI .SRT, an altitude .csv or a laser log")
    add_altitude_offsets(parser)
    parser.add_argument("--clip", type=Path, default=None, help="align to this video's frames")
    parser.add_argument("--gps-clock", nargs=2, default=None, metavar=("UTC", "FRAME"),
                        help="laser logs: a GPS clock filmed in --clip reads UTC "
                             "('YYYY/MM/DD HH:MM:SS.s') at frame FRAME; the time offset is "
                             "taken from it (instead of --time-offset)")
    parser.add_argument("--out", type=Path, default=None, metavar="FILE.csv",
                        help="write the altitudes as CSV")


def run(args: argparse.Namespace) -> int:
    """Read, summarise, and write the CSV if asked."""
    check_altitude_offsets(args)
    if args.out is not None:
        check_output_file(args.out, "--out ")
    clip = open_clip(args.clip) if args.clip is not None else None
    time_offset = args.time_offset if args.gps_clock is None else _clock_offset(args, clip)
    samples = read_altitude(args.file, args.launch_height, time_offset)
    if clip is None and samples.time_s is None:
        raise InputError(f"{args.file}: rows are keyed by frame; give --clip to place them "
                         "in time")
    telemetry = align_to_frames(samples, clip) if clip is not None else None
    print(format_summary(samples, telemetry, clip.fps if clip is not None else None))
    if args.out is not None:
        if telemetry is None:
            write_altitude_csv(args.out, {"time_s": samples.time_s,
                                          "altitude_m": samples.altitude_m})
        else:
            write_altitude_csv(args.out, {
                "frame": range(telemetry.num_frames), "time_s": telemetry.time_s,
                "altitude_m": telemetry.altitude_m, "is_interpolated": telemetry.is_interpolated,
            })
        print(f"wrote {args.out}")
    return 0


def _clock_offset(args: argparse.Namespace, clip: Clip | None) -> float:
    """The time offset from ``--gps-clock UTC FRAME`` (a LidarBoX log and --clip needed)."""
    if clip is None:
        raise InputError("--gps-clock needs --clip, the video that filmed the clock")
    if args.time_offset != 0.0:
        raise InputError("give --gps-clock or --time-offset, not both")
    if not is_laser_log(args.file):
        raise InputError(f"--gps-clock: {args.file} is not a LidarBoX laser log (only its "
                         "rows carry GPS time)")
    utc, frame = args.gps_clock
    clock = parse_clock_time(utc, "--gps-clock")
    try:
        frame_idx = count(int(frame), 0, "--gps-clock frame")
    except ValueError:
        raise InputError(f"--gps-clock frame {frame!r}: expected a whole number") from None
    if frame_idx >= clip.num_frames:
        raise InputError(f"--gps-clock frame {frame_idx}: {clip.path.name} has "
                         f"{clip.num_frames} frames")
    offset = gps_clock_offset_s(args.file, clock, frame_idx / clip.fps)
    print(f"time offset {offset:.3f} s (the GPS clock read {utc} at frame {frame_idx}, "
          f"{frame_idx / clip.fps:.3f} s into {clip.path.name})")
    return offset


def format_summary(samples: AltitudeSamples, telemetry: Telemetry | None,
                   fps: float | None) -> str:
    """Source, family, sample rate, altitude range, gaps, warnings and the frame alignment."""
    source = samples.source
    summary = summarize_samples(samples, fps)
    kind = SOURCE_NAMES[source.kind]
    if source.kind == "srt":
        kind += f", {source.family} family ({FAMILIES[source.family].models})"
    elif source.kind == "laser":
        kind += f" ({LOGGER_NAMES[source.family]})"
    field = source.field or "none"
    if source.is_relative:
        field += f" (relative to take-off) + launch height {source.launch_height_m:.2f} m"
    gaps = ", ".join(f"{start:g} s ({length:g} s)" for start, length in summary.gaps[:5])
    lines = [
        f"file       {source.path}",
        f"source     {kind}",
        f"altitude   {field}",
        f"samples    {summary.num_samples}, {summary.num_valid} with altitude, "
        f"{summary.start_s:g}–{summary.end_s:g} s, {summary.rate_hz:.4g} Hz",
        "range      " + ("none" if math.isnan(summary.min_altitude_m) else
                         f"{summary.min_altitude_m:.2f} … {summary.max_altitude_m:.2f} m"),
        "gaps       " + (f"{len(summary.gaps)}: {gaps}" if gaps else "none"),
    ]
    if source.kind == "laser":
        lines.append(f"offset     {source.time_offset_s:g} s")
    if telemetry is not None:
        missing = int(telemetry.is_missing.sum())
        lines.append(f"frames     {telemetry.num_frames}: {missing} missing"
                     + (f" ({format_runs(telemetry.is_missing)})" if missing else "")
                     + f", {int(telemetry.is_interpolated.sum())} interpolated")
    lines += [f"warning    {w}" for w in (telemetry or samples).warnings]
    return "\n".join(lines)
