"""Read an altitude source, summarise it and optionally write it as CSV.

  dolphinfit telemetry FILE [--launch-height M] [--time-offset S] [--clip CLIP]
                            [--out FILE.csv]

FILE is a DJI .SRT of any family (modern rel_alt/abs_alt, html-bracket altitude, single-line
H, Matrice 300 and legacy BAROMETER or Hb), an altitude CSV (frame,altitude_m or
time_s,altitude_m), a LidarBoX laser log (laser_altitude_cm × cos(tilt_deg)) or a Freefly
Astro flight log (its camera range).
--launch-height adds the take-off point's height above the water to relative altitudes.
--time-offset is the laser-log time (s after its first row) at which the clip starts.
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
from dolphinfit.core.io.video import open_clip
from dolphinfit.app.commands.altitude_options import add_altitude_offsets, check_altitude_offsets

SOURCE_NAMES = {"srt": "DJI SRT", "csv": "altitude CSV", "laser": "laser log"}
LOGGER_NAMES = {"lidarbox": "LidarBoX", "freefly-astro": "Freefly Astro"}  # by source.family


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The file, the launch height, the time offset, the clip and the output."""
    parser.add_argument("file", type=Path, help="a DJI .SRT, an altitude .csv or a laser log")
    add_altitude_offsets(parser)
    parser.add_argument("--clip", type=Path, default=None, help="align to this video's frames")
    parser.add_argument("--out", type=Path, default=None, metavar="FILE.csv",
                        help="write the altitudes as CSV")


def run(args: argparse.Namespace) -> int:
    """Read, summarise, and write the CSV if asked."""
    check_altitude_offsets(args)
    if args.out is not None:
        check_output_file(args.out, "--out ")
    samples = read_altitude(args.file, args.launch_height, args.time_offset)
    clip = open_clip(args.clip) if args.clip is not None else None
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
