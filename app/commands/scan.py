"""Find the animals in clips and the frames worth measuring each of them in.

  dolphinfit scan CLIP|FOLDER --out DIR [--altitude M|FILE] [--launch-height M]
                  [--time-offset S] [--camera PRESET |
                  --sensor-width-mm W --focal-mm F] [--fps F] [--search-every S]
                  [--tile-search-every S] [--best N] [--altitude-range LOW,HIGH]
                  [--max-gimbal-off DEG]

Samples each clip (--fps frames per second, default 1), finds every animal in view as the
automatic seed does (the whole frame and its tiles every --tile-search-every seconds, default
15; between, each animal around where it was, and a look at the whole frame for animals
coming into view every --search-every seconds, default 5), follows each across the samples under one number, and scores
every sampled frame for measuring each animal: its length relative to its longest
(pitched, diving or arched bodies read short), the body's straightness, the sharpness of its
outline, its contrast to the water (at the surface or under it), its distance to the frame's
edge, the altitude (within --altitude-range where given) and, where the SRT records it, the
gimbal's pitch. Writes DIR/STEM_scan.csv (one row per animal and sampled frame, the best
--best frames of each ranked) and DIR/STEM_scan.json, and prints each animal's best frames.

A FOLDER scans every video in it (each with the SRT beside it, or --altitude for all) and
lists every clip it could not use with the reason. The altitude comes from the clip's SRT
unless --altitude gives a number or a file; the camera from --camera or explicit values
(default: the default preset).
"""

import argparse
import sys
from pathlib import Path

from dolphinfit.app.commands.altitude_options import add_altitude_offsets, check_altitude_offsets
from dolphinfit.app.progress import is_tenth
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.pipeline import CameraChoice
from dolphinfit.core.io.frame_source import Clip
from dolphinfit.core.io.media import video_files
from dolphinfit.core.io.output_paths import check_output_folder
from dolphinfit.core.io.telemetry import load_telemetry
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.limits import count, positive
from dolphinfit.core.progress import Progress, ProgressCallback
from dolphinfit.core.scan.clip_scan import ClipScan, ClipTelemetry, scan_telemetry
from dolphinfit.core.scan.scanner import Scanner
from dolphinfit.core.scan.frame_scores import ScanSettings
from dolphinfit.core.scan.scan_files import write_scan_csv, write_scan_json

def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The clips, the output, the camera and altitude, and the scan's settings."""
    parser.add_argument("clips", type=Path, metavar="CLIP|FOLDER",
                        help="a video, or a folder of videos")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR",
                        help="folder for STEM_scan.csv and STEM_scan.json")
    parser.add_argument("--altitude", default=None, metavar="M|FILE",
                        help="metres above the water, or an altitude file, for every clip "
                             "(default: each clip's SRT)")
    add_altitude_offsets(parser)
    parser.add_argument("--camera", default=None, metavar="PRESET", help="camera preset name")
    parser.add_argument("--sensor-width-mm", type=float, default=None)
    parser.add_argument("--focal-mm", type=float, default=None)
    defaults = ScanSettings()
    parser.add_argument("--fps", type=float, default=defaults.sample_fps,
                        help=f"frames sampled per second (default {defaults.sample_fps:g})")
    parser.add_argument("--search-every", type=float, default=defaults.search_every_s,
                        metavar="S", help="seconds between looks at the whole frame for "
                                          "animals coming into view "
                                          f"(default {defaults.search_every_s:g})")
    parser.add_argument("--tile-search-every", type=float,
                        default=defaults.tile_search_every_s, metavar="S",
                        help="seconds between full searches of the frame in tiles "
                             f"(default {defaults.tile_search_every_s:g})")
    parser.add_argument("--best", type=int, default=defaults.best_count, metavar="N",
                        help=f"best frames listed per animal (default {defaults.best_count})")
    parser.add_argument("--altitude-range", default=None, metavar="LOW,HIGH",
                        help="altitudes (m) a usable frame must lie within")
    parser.add_argument("--max-gimbal-off", type=float, default=defaults.max_gimbal_off_deg,
                        metavar="DEG", help="how far from straight down the gimbal may point "
                                            f"(default {defaults.max_gimbal_off_deg:g}°)")


def scan_settings(args: argparse.Namespace) -> ScanSettings:
    """The settings from the options, checked at the boundary."""
    altitude_range = None
    if args.altitude_range is not None:
        try:
            low, high = (float(v) for v in args.altitude_range.split(","))
        except ValueError:
            raise InputError(f"--altitude-range {args.altitude_range!r}: expected LOW,HIGH in "
                             "metres") from None
        if not 0 < low < high:
            raise InputError(f"--altitude-range {args.altitude_range!r}: expected "
                             "0 < LOW < HIGH")
        altitude_range = (low, high)
    return ScanSettings(sample_fps=positive(args.fps, "--fps"),
                        search_every_s=positive(args.search_every, "--search-every"),
                        tile_search_every_s=positive(args.tile_search_every,
                                                     "--tile-search-every"),
                        altitude_range_m=altitude_range,
                        max_gimbal_off_deg=positive(args.max_gimbal_off, "--max-gimbal-off"),
                        best_count=count(args.best, 1, "--best"))


def clip_telemetry(path: Path, args: argparse.Namespace, camera: CameraChoice,
                   warnings: list[str]) -> tuple[ClipTelemetry, Clip]:
    """The clip (opened and checked) and what the scan knows of its camera: altitude per
    frame, focal length in pixels, and the gimbal's pitch where the SRT records it;
    InputError naming the clip when it cannot be used."""
    clip = open_clip(path)
    telemetry = load_telemetry(clip, args.altitude, args.launch_height, args.time_offset)
    warnings.extend(telemetry.warnings)
    return scan_telemetry(clip, telemetry, camera.intrinsics(clip).focal_px), clip


def _progress(name: str) -> ProgressCallback:
    """A stderr line per tenth of a clip's samples."""
    def show(progress: Progress) -> None:
        if is_tenth(progress):
            print(f"{name}: {progress.step}/{progress.total} samples; {progress.message}",
                  file=sys.stderr)
    return show


def summary_lines(scan: ClipScan) -> list[str]:
    """What a scan found, for the terminal: each animal with its best frames."""
    ids = scan.animal_ids()
    lines = [f"{scan.clip_name}: {len(ids)} animal{'s' if len(ids) != 1 else ''} in "
             f"{len(scan.sampled_frames)} sampled frames ({scan.seconds:.0f} s)"
             + ("; none found: check the clip (the scan may have missed an animal)"
                if not ids else "")]
    for animal in ids:
        scores = scan.of_animal(animal)
        best = scan.best(animal)
        usable = sum(score.is_usable for score in scores)
        picks = ", ".join(f"{s.frame_idx} ({s.quality:.2f})" for s in best) or "none usable"
        lines.append(f"  animal {animal}: seen in {len(scores)}, usable in {usable}; best "
                     f"frames (quality) {picks}")
    return lines


def run(args: argparse.Namespace) -> int:
    """Scan each clip and write its files; exit 2 when no clip could be scanned."""
    check_altitude_offsets(args)
    settings = scan_settings(args)
    out = check_output_folder(args.out, "--out ")
    camera = CameraChoice(args.camera, args.sensor_width_mm, args.focal_mm)
    paths = video_files(args.clips)
    scanner, failed = Scanner(), []
    for path in paths:
        warnings: list[str] = []
        try:
            telemetry, clip = clip_telemetry(path, args, camera, warnings)
        except InputError as exc:
            failed.append(str(exc))
            continue
        for warning in warnings:
            print(f"warning: {warning}", file=sys.stderr)
        with VideoReader(clip) as frames:
            scan = scanner.scan(frames, telemetry, settings, _progress(path.name))
        out.mkdir(parents=True, exist_ok=True)
        write_scan_json(out / f"{path.stem}_scan.json", scan)
        write_scan_csv(out / f"{path.stem}_scan.csv", scan)
        print("\n".join(summary_lines(scan)))
    if len(paths) > 1:
        for reason in failed:
            print(f"not scanned: {reason}", file=sys.stderr)
    if len(paths) == 1 and failed:
        raise InputError(failed[0])
    if len(failed) == len(paths):
        raise InputError(f"{args.clips}: no clip could be scanned")
    return 0
