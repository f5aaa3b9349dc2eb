"""Elliptical baseline: length, volume, BCI and mass with 95 % intervals, and the exports.

  dolphinfit measure ANNOTATION.json [--hw PRESET|CSV|model] [--tail extrapolated|measured]
                     [--mc N] [--seed S] [--out DIR] [--from-mask MASKS]
                     [--altitude-m M] [--altitude-source laser|barometer|manual]
                     [--digitisation-sd-px PX] [--altitude-sd-fraction F]
                     [--focal-sd-fraction F] [--mass-model JSON]
  dolphinfit measure MORPHOMETRIX.csv [same options]

The input is a dolphinfit annotation (JSON) or a MorphoMetriX v1/v2 CSV. Volume is the sum of
20 elliptical frustums (Christiansen et al. 2019); heights are widths × HW ratio from a preset
(default tursiops-provisional), your CSV, or "model" (the 3D template). --tail extrapolated
(default, CollatriX and the paper) ignores the 90/95 % widths and tapers from 85 %; measured
uses them. --from-mask takes each width where the station's perpendicular leaves the annotated
frame's mask (a folder of %06d.png, an .npz or a mask video; non-zero = dolphin). --mc N draws
N Monte Carlo samples (0: none) over altitude, camera, digitisation and HW-ratio errors, with
defaults by altitude source (laser 1 %, barometer 5 %, manual 10 %).

Writes DIR/<name>_measure.json, DIR/<name>_mmx.csv (MorphoMetriX v2 long) and
DIR/<name>_wide.csv (CollatriX / Xcertainty); DIR defaults to the input's folder.
"""

import argparse
import math
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

from core.errors import InputError
from core.io.annotation_json import AnnotationFile, read_annotation_json
from core.io.collatrix import wide_row, write_wide_csv
from core.io.json_file import read_json, write_json
from core.io.masks import read_masks
from core.io.morphometrix import (
    LENGTH_NAME, MorphoMetrixRecord, read_morphometrix, record_from_pixels,
    write_morphometrix_v2,
)
from core.io.morphometrix import pixel_measurements as record_pixels
from core.measure.annotation import (
    ALTITUDE_SOURCES, PixelMeasurements, pixel_measurements, place_stations, suggest_edges,
)
from core.measure.baseline import (
    SUMMARISED, BaselineEstimate, BaselineSettings, estimate_baseline,
)
from core.measure.condition import MassModel
from core.measure.elliptical import TAIL_EXTRAPOLATED, TAIL_OPTIONS
from core.measure.hw_ratios import DEFAULT_PRESET, FROM_MODEL, resolve_hw
from core.measure.uncertainty import DEFAULT_NUM_DRAWS, ErrorModel
from core.model.profile import STATION_FRACTIONS

RESULT_SCHEMA_VERSION = 1
MMX_ALTITUDE_SOURCE = "manual"  # MorphoMetriX altitudes are typed in; the source is unknown
ROWS = (  # printed quantity, unit, format
    ("length_m", "m", ".3f"), ("volume_m3", "m³", ".4f"), ("volume_circular_m3", "m³", ".4f"),
    ("bai", "", ".2f"), ("bci", "", "+.3f"), ("mass_kg", "kg", ".1f"),
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The input file and the options of the module docstring."""
    parser.add_argument("input", type=Path,
                        help="annotation (.json) or MorphoMetriX measurements (.csv)")
    parser.add_argument("--hw", default=DEFAULT_PRESET, metavar="PRESET|CSV|model",
                        help=f"HW ratios (default: %(default)s; {FROM_MODEL}: the 3D template)")
    parser.add_argument("--tail", choices=TAIL_OPTIONS, default=TAIL_EXTRAPOLATED,
                        help="90/95 %% widths: extrapolated from 85 %% or measured "
                             "(default: %(default)s)")
    parser.add_argument("--mc", type=int, default=DEFAULT_NUM_DRAWS, metavar="N",
                        help="Monte Carlo draws, 0 for none (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="Monte Carlo seed (default: 0)")
    parser.add_argument("--out", type=Path, default=None, metavar="DIR",
                        help="output folder (default: the input's folder)")
    parser.add_argument("--from-mask", type=Path, default=None, metavar="MASKS",
                        help="take the widths from the annotated frame's mask: a folder of "
                             "%%06d.png, an .npz or a mask video (annotations only)")
    parser.add_argument("--altitude-m", type=float, default=None,
                        help="replace the stored altitude, metres")
    parser.add_argument("--altitude-source", choices=ALTITUDE_SOURCES, default=None,
                        help="replace the stored altitude source")
    parser.add_argument("--digitisation-sd-px", type=float, default=None,
                        help="SD of one click per image axis, px")
    parser.add_argument("--altitude-sd-fraction", type=float, default=None,
                        help="relative SD of the altitude (default by source)")
    parser.add_argument("--focal-sd-fraction", type=float, default=None,
                        help="relative SD of the focal length in pixels")
    parser.add_argument("--mass-model", type=Path, default=None, metavar="JSON",
                        help="JSON object overriding mass-model constants "
                             f"({', '.join(f.name for f in fields(MassModel))})")


@dataclass(frozen=True)
class MeasureInput:
    """An input file brought to pixels, calibration and export metadata."""

    pixels: PixelMeasurements
    record: MorphoMetrixRecord      # metadata and measurements as exported
    focal_px: float
    altitude_source: str
    is_camera_approximate: bool
    notes: list[str]                # printed above the table
    image_width_px: int | None = None   # Xcertainty's Iw, Sw and uas (annotations only)
    sensor_width_mm: float | None = None
    uas: str = ""


def run(args: argparse.Namespace) -> int:
    """Measure, print the table and write the exports."""
    _check_options(args)
    source = (_from_annotation(args) if args.input.suffix.lower() == ".json"
              else _from_morphometrix(args))
    settings = BaselineSettings(hw=resolve_hw(args.hw), tail=args.tail,
                                mass_model=_mass_model(args.mass_model))
    try:
        estimate = estimate_baseline(source.pixels, source.focal_px, source.record.altitude_m,
                                     settings, _error_model(args, source), args.mc,
                                     np.random.default_rng(args.seed))
    except ValueError as exc:
        raise InputError(f"{args.input}: {exc}") from exc
    result = {"schema_version": RESULT_SCHEMA_VERSION, "input": str(args.input),
              "altitude_m": source.record.altitude_m, "altitude_source": source.altitude_source,
              "focal_px": source.focal_px, "seed": args.seed, **estimate.to_json()}
    print(format_report(args.input, source, estimate, result))
    out_dir = args.out if args.out is not None else args.input.parent
    for path in _write_exports(out_dir / args.input.stem, source, estimate, result):
        print(f"wrote {path}")
    return 0


def _check_options(args: argparse.Namespace) -> None:
    """InputError for option values outside their range."""
    if args.mc < 0 or args.mc == 1:
        raise InputError(f"--mc must be 0 (no Monte Carlo) or at least 2, got {args.mc}")
    if args.altitude_m is not None and not (math.isfinite(args.altitude_m)
                                            and args.altitude_m > 0):
        raise InputError(f"--altitude-m must be positive, got {args.altitude_m}")
    for option in ("digitisation_sd_px", "altitude_sd_fraction", "focal_sd_fraction"):
        value = getattr(args, option)
        if value is not None and not (math.isfinite(value) and value >= 0):
            raise InputError(f"--{option.replace('_', '-')} must be a non-negative number, "
                             f"got {value}")


def _from_annotation(args: argparse.Namespace) -> MeasureInput:
    """Pixels and metadata of an annotation file (widths from a mask if asked)."""
    doc = read_annotation_json(args.input)
    calibration = doc.calibration
    if args.altitude_m is not None or args.altitude_source is not None:
        calibration = replace(calibration,
                              altitude_m=args.altitude_m or calibration.altitude_m,
                              altitude_source=args.altitude_source or calibration.altitude_source)
    annotation = doc.annotation
    if args.from_mask is not None:
        mask = _frame_mask(args.from_mask, annotation.frame_idx,
                           calibration.camera.image_height_px, calibration.camera.image_width_px)
        edges = suggest_edges(mask, place_stations(annotation.midline_px))
        annotation = replace(annotation, edges_px=edges)
    pixels = pixel_measurements(annotation)
    camera = calibration.camera
    record = record_from_pixels(
        pixels, image_id=_image_id(doc, args.input), image_path=doc.media_path,
        focal_mm=camera.focal_mm, pixel_dimension_mm=camera.sensor_width_mm
        / camera.image_width_px, altitude_m=calibration.altitude_m,
        mirror_side=annotation.mirror_side, notes=doc.notes)
    return MeasureInput(
        pixels=pixels, record=record, focal_px=calibration.focal_px,
        altitude_source=calibration.altitude_source, is_camera_approximate=camera.approximate,
        notes=[f"frame {annotation.frame_idx}, camera {calibration.preset_name or 'explicit'}"
               f" (focal {calibration.focal_px:.1f} px)"]
        + ([f"widths from the mask {args.from_mask}"] if args.from_mask else []),
        image_width_px=camera.image_width_px, sensor_width_mm=camera.sensor_width_mm,
        uas=calibration.preset_name or "")


def _image_id(doc: AnnotationFile, path: Path) -> str:
    return doc.image_id or f"{path.stem} frame {doc.annotation.frame_idx}"


def _from_morphometrix(args: argparse.Namespace) -> MeasureInput:
    """Pixels and metadata of a MorphoMetriX CSV."""
    if args.from_mask is not None:
        raise InputError("--from-mask needs an annotation (.json) with a midline")
    record = read_morphometrix(args.input)
    pixels = record_pixels(record, args.input)
    if args.altitude_m is not None:
        record = replace(record, altitude_m=args.altitude_m)
    notes = [f"MorphoMetriX v{record.version} file, focal {record.focal_px:.1f} px"]
    if args.altitude_source is None:
        notes.append(f"altitude source unknown: taken as {MMX_ALTITUDE_SOURCE} "
                     f"(use --altitude-source)")
    if record.version == 1:
        notes.append("v1 files hold metres rounded to cm only: pixels derived from them")
    if pixels.is_mirrored:
        notes.append("mirror-side widths: MorphoMetriX v2 may store one side undoubled; check")
    exported = record_from_pixels(
        pixels, image_id=record.image_id, image_path=record.image_path,
        focal_mm=record.focal_mm, pixel_dimension_mm=record.pixel_dimension_mm,
        altitude_m=record.altitude_m, mirror_side=record.mirror_side, notes=record.notes)
    return MeasureInput(pixels=pixels, record=exported, focal_px=record.focal_px,
                        altitude_source=args.altitude_source or MMX_ALTITUDE_SOURCE,
                        is_camera_approximate=False, notes=notes)


def _frame_mask(path: Path, frame_idx: int, height_px: int, width_px: int) -> np.ndarray:
    """(H, W) bool mask of the annotated frame from a mask source (core.io.masks formats)."""
    track = read_masks(path)
    if (track.height_px, track.width_px) != (height_px, width_px):
        raise InputError(f"{path}: masks are {track.width_px}×{track.height_px} px but the "
                         f"camera's frames are {width_px}×{height_px} px")
    if not (0 <= frame_idx < track.num_frames and track.is_visible[frame_idx]):
        raise InputError(f"{path}: no dolphin in the mask of frame {frame_idx}")
    return track.mask(frame_idx)


def _mass_model(path: Path | None) -> MassModel:
    """Mass-model constants: the paper's, overridden by a JSON object's entries."""
    if path is None:
        return MassModel()
    data = read_json(path, "the mass model")
    names = {f.name for f in fields(MassModel)}
    if not isinstance(data, dict) or not set(data) <= names:
        raise InputError(f"{path}: expected an object with keys among {', '.join(sorted(names))}")
    if "bci_fit_range" in data:
        data["bci_fit_range"] = tuple(data["bci_fit_range"])
    try:
        return MassModel(**data)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{path}: {exc}") from exc


def _error_model(args: argparse.Namespace, source: MeasureInput) -> ErrorModel:
    """Defaults by altitude source and camera, overridden by the options given."""
    errors = ErrorModel.default(source.altitude_source, source.is_camera_approximate)
    overrides = {name: getattr(args, name) for name in
                 ("altitude_sd_fraction", "focal_sd_fraction", "digitisation_sd_px")
                 if getattr(args, name) is not None}
    return replace(errors, **overrides)


def format_report(path: Path, source: MeasureInput, estimate: BaselineEstimate,
                  result: dict) -> str:
    """The printed table: nominal value, mean ± SD and 95 % interval of each quantity."""
    settings, record = estimate.settings, source.record
    lines = [f"{path}: {'; '.join(source.notes)}",
             f"altitude {record.altitude_m:g} m ({source.altitude_source}), "
             f"{estimate.m_per_px * 1000:.3f} mm/px; HW ratios {settings.hw.name}; "
             f"tail {settings.tail}", ""]
    mc = estimate.interval
    header = f"{'':20s}{'value':>9s}"
    if mc is not None:
        header += f"{'mean ± SD':>20s}          95 % interval ({mc.num_draws} draws)"
    lines.append(header)
    for name, unit, fmt in ROWS:
        line = f"{name:20s}{format(result[name], fmt):>9s} {unit:3s}"
        if mc is not None:
            s = getattr(mc, name)
            spread = f"{format(float(s.mean), fmt):>10s} ± {format(float(s.sd), fmt.lstrip('+'))}"
            line += f"{spread:27s}[{format(float(s.low), fmt)}, {format(float(s.high), fmt)}]"
        lines.append(line.rstrip())
    if estimate.budget:
        lines += ["", "volume / mass SD by error source alone:"]
        lines += [f"  {name:14s}{float(r.volume_m3.sd):.4f} m³   {float(r.mass_kg.sd):.1f} kg"
                  for name, r in estimate.budget.items()]
    lines += [f"warning: {text}" for text in result["warnings"]]
    return "\n".join(lines)


def _write_exports(stem: Path, source: MeasureInput, estimate: BaselineEstimate,
                   result: dict) -> list[Path]:
    """Write STEM_measure.json, STEM_mmx.csv (MorphoMetriX v2) and STEM_wide.csv."""
    paths = [stem.with_name(f"{stem.name}{suffix}")
             for suffix in ("_measure.json", "_mmx.csv", "_wide.csv")]
    write_json(paths[0], result)
    write_morphometrix_v2(paths[1], source.record)
    write_wide_csv(paths[2], [wide_row(
        source.record, image=paths[1].name, altitude_source=source.altitude_source,
        image_width_px=source.image_width_px, sensor_width_mm=source.sensor_width_mm,
        uas=source.uas, extras=_result_columns(estimate, result))])
    return paths


def _result_columns(estimate: BaselineEstimate, result: dict) -> dict[str, object]:
    """Wide-CSV result columns: HW ratios used (CollatriX names), values and intervals."""
    ratios, _ = estimate.settings.hw.completed()
    columns: dict[str, object] = {f"{LENGTH_NAME}_ratio{pct:.2f}": float(r)
                                  for pct, r in zip(STATION_FRACTIONS * 100, ratios)}
    columns.update({"tail": estimate.settings.tail, "hw_ratios": estimate.settings.hw.name})
    if estimate.settings.tail == TAIL_EXTRAPOLATED:
        columns["BVell_5perc"] = result["volume_m3"]  # CollatriX's elliptical volume, same method
    for name in SUMMARISED:
        columns[name] = result[name]
        if estimate.interval is not None:
            s = getattr(estimate.interval, name)
            columns.update({f"{name}_sd": float(s.sd), f"{name}_lo95": float(s.low),
                            f"{name}_hi95": float(s.high)})
    return columns
