"""Elliptical baseline: length, volume, BCI and mass with 95 % intervals, and the exports.

  dolphinfit measure ANNOTATION.json [--hw PRESET|CSV|model] [--tail extrapolated|measured]
                     [--mc N] [--seed S] [--out DIR] [--from-mask MASKS]
                     [--altitude-m M] [--altitude-source laser|barometer|manual]
                     [--digitisation-sd-px PX] [--altitude-sd-fraction F]
                     [--focal-sd-fraction F] [--mass-model JSON]
                     [--altitude-calibration CAL.json] [--lens LENS.json]
                     [--subject ID] [--mmx-version 1|2]
  dolphinfit measure MORPHOMETRIX.csv [--length-name NAME] [same options]
  dolphinfit measure --from-mask MASKS --altitude-m M
                     (--camera PRESET | --sensor-width-mm X --focal-mm Y) [--frame N]
                     [same options]

The input is a dolphinfit annotation (JSON), a MorphoMetriX v1/v2 CSV, or a mask alone. In a
MorphoMetriX file the total length is the row named TL, Total_Length, Total Length or Body
Length, whatever its case, spaces and underscores (--length-name names another); the exports
name it TL, so that a lab's past measurements pool with ours under the same columns. Without
an annotation, --from-mask takes the midline from the mask too, as `dolphinfit batch` does
(rostrum tip to fluke notch; nobody reviews it), on frame --frame (default: where the mask is
largest), with the camera of --camera or --sensor-width-mm and --focal-mm at the mask's size
and the altitude of --altitude-m (source --altitude-source, default manual). Volume is the sum of
20 elliptical frustums (Christiansen et al. 2019); heights are widths × HW ratio from a preset
(default tursiops-provisional), your CSV, or "model" (the 3D template). --tail extrapolated
(default, CollatriX and the paper) ignores the 90/95 % widths and tapers from 85 %; measured
uses them. --from-mask takes each width where the station's perpendicular leaves the annotated
frame's mask (a folder of %06d.png, an .npz or a mask video; non-zero = dolphin). --mc N draws
N Monte Carlo samples (0: none) over altitude, camera, digitisation and HW-ratio errors, with
defaults by altitude source (laser 1 %, barometer 5 %, manual 10 %). --altitude-calibration
corrects the altitude by a calibration of the image's camera (`dolphinfit calibrate altitude`)
and takes the altitude error from its spread instead. --lens takes the clicks through a lens
model (`dolphinfit calibrate lens`) before measuring; without one, a frame measured more than
half-way to its corner is warned about.

Writes DIR/<name>_measure.json, DIR/<name>_mmx.csv (MorphoMetriX v2 long; v1 blocks with
--mmx-version 1, as MorphoMetriX v1 wrote them: metres only, no mirror side), DIR/<name>_wide.csv
(ours: metres, pixels, Xcertainty's columns, results), DIR/<name>_collatrix.csv (the table
CollatriX's body-condition tool reads) and, for an annotation, DIR/<name>_xcertainty.csv (the
row Xcertainty's parse_observations reads; --subject names the animal, default the image ID);
DIR defaults to the input's folder; <name> is the input's (the mask's, without one). The
records are built by core/measure/records.py, shared with the GUI.
"""

import argparse
from dataclasses import fields, replace
from pathlib import Path

import numpy as np

from dolphinfit.core.camera_presets import (
    CameraPreset, get_preset, preset_resolution_mismatch,
)
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import MaskTrack, read_masks
from dolphinfit.core.measure.annotation_json import AnnotationFile, read_annotation_json
from dolphinfit.core.io.output_paths import check_output_folder
from dolphinfit.core.limits import (
    ALTITUDE_M, FOCAL_MM, SENSOR_WIDTH_MM, at_least, body_measurements, count, in_range,
    result_figures,
)
from dolphinfit.core.measure.altitude_calibration import (
    AltitudeCalibration, read_altitude_calibration,
)
from dolphinfit.core.measure.annotation import ALTITUDE_SOURCES, Calibration
from dolphinfit.core.measure.baseline import BaselineEstimate, BaselineSettings, estimate_baseline
from dolphinfit.core.measure.condition import MassModel
from dolphinfit.core.measure.elliptical import TAIL_EXTRAPOLATED, TAIL_OPTIONS
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET, FROM_MODEL
from dolphinfit.core.measure.lens import read_lens, through_lens
from dolphinfit.core.measure.mask_midline import annotation_from_mask
from dolphinfit.core.measure.morphometrix import MMX_VERSIONS
from dolphinfit.core.measure.preset_lens import preset_lens
from dolphinfit.core.model.hw_spec import resolve_hw
from dolphinfit.core.measure.records import (
    MeasureInput, annotated_frame_mask, default_error_model, default_image_id,
    with_altitude_calibration,
    mass_model_from_json, measured_image_from_annotation, measured_image_from_morphometrix,
    result_record, with_mask_widths, write_exports,
)
from dolphinfit.core.measure.uncertainty import DEFAULT_NUM_DRAWS, ErrorModel
from dolphinfit.core.measure.xcertainty import observation_row
from dolphinfit.core.measure.collatrix import write_wide_csv

MASK_ALTITUDE_SOURCE = "manual"  # an altitude typed on the command line, unless told otherwise
MASK_NOTE = "midline and widths from the mask, not reviewed"
MASK_ONLY_OPTIONS = ("camera", "sensor_width_mm", "focal_mm", "frame")
ROWS = (  # printed quantity, unit, format
    ("length_m", "m", ".3f"), ("volume_m3", "m³", ".4f"), ("volume_circular_m3", "m³", ".4f"),
    ("bai", "", ".2f"), ("bci", "", "+.3f"), ("mass_kg", "kg", ".1f"),
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The input file and the options of the module docstring."""
    parser.add_argument("input", type=Path, nargs="?", default=None,
                        help="annotation (.json) or MorphoMetriX measurements (.csv); none "
                             "with --from-mask: the midline from the mask too")
    parser.add_argument("--hw", default=DEFAULT_PRESET, metavar="PRESET|CSV|model",
                        help=f"HW ratios (default: %(default)s; {FROM_MODEL}: the 3D template)")
    parser.add_argument("--tail", choices=TAIL_OPTIONS, default=TAIL_EXTRAPOLATED,
                        help="90/95 %% widths: extrapolated from 85 %% or measured "
                             "(default: %(default)s)")
    parser.add_argument("--mc", type=int, default=DEFAULT_NUM_DRAWS, metavar="N",
                        help="Monte Carlo draws, 0 for none (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="Monte Carlo seed (default: 0)")
    parser.add_argument("--subject", default=None, metavar="ID",
                        help="the animal's ID in the Xcertainty table (default: the image ID)")
    parser.add_argument("--out", type=Path, default=None, metavar="DIR",
                        help="output folder (default: the input's folder)")
    parser.add_argument("--from-mask", type=Path, default=None, metavar="MASKS",
                        help="take the widths from the annotated frame's mask (without an "
                             "annotation, the midline too): a mask image, a folder of "
                             "%%06d.png, an .npz or a mask video")
    parser.add_argument("--frame", type=int, default=None, metavar="N",
                        help="the mask's frame to measure, without an annotation (default: "
                             "where the mask is largest)")
    parser.add_argument("--camera", default=None, metavar="PRESET",
                        help="camera preset of the mask, without an annotation")
    parser.add_argument("--sensor-width-mm", type=float, default=None,
                        help="sensor width of the mask's camera, without an annotation")
    parser.add_argument("--focal-mm", type=float, default=None,
                        help="real focal length of the mask's camera, without an annotation")
    parser.add_argument("--length-name", default=None, metavar="NAME",
                        help="the total length's row in a MorphoMetriX file (default: TL, "
                             "Total_Length, Total Length … in any case)")
    parser.add_argument("--mmx-version", type=int, choices=MMX_VERSIONS, default=2,
                        help="MorphoMetriX version of the _mmx.csv export: 2 long (metres "
                             "and pixels) or 1 blocks (metres) (default: %(default)s)")
    parser.add_argument("--altitude-m", type=float, default=None,
                        help="replace the stored altitude, metres")
    parser.add_argument("--altitude-source", choices=ALTITUDE_SOURCES, default=None,
                        help="replace the stored altitude source")
    parser.add_argument("--altitude-calibration", type=Path, default=None, metavar="CAL.json",
                        help="correct the altitude with a calibration from `dolphinfit "
                             "calibrate altitude` (its spread becomes the altitude's SD)")
    parser.add_argument("--lens", type=Path, default=None, metavar="LENS.json",
                        help="take the clicks through the camera's lens model from `dolphinfit "
                             "calibrate lens` (annotations only)")
    parser.add_argument("--digitisation-sd-px", type=float, default=None,
                        help="SD of one click per image axis, px")
    parser.add_argument("--altitude-sd-fraction", type=float, default=None,
                        help="relative SD of the altitude (default by source)")
    parser.add_argument("--focal-sd-fraction", type=float, default=None,
                        help="relative SD of the focal length in pixels")
    parser.add_argument("--mass-model", type=Path, default=None, metavar="JSON",
                        help="JSON object overriding mass-model constants "
                             f"({', '.join(f.name for f in fields(MassModel))})")


def run(args: argparse.Namespace) -> int:
    """Measure, print the table and write the exports."""
    _check_options(args)
    named = args.input if args.input is not None else args.from_mask  # names the outputs
    source = (_from_mask_alone(args) if args.input is None
              else _from_annotation(args) if args.input.suffix.lower() == ".json"
              else _from_morphometrix(args))
    calibration = None
    if args.altitude_calibration is not None:
        calibration = read_altitude_calibration(args.altitude_calibration)
        source = with_altitude_calibration(source, calibration, str(named))
    _check_body(source, named)
    mass_model = (MassModel() if args.mass_model is None
                  else mass_model_from_json(args.mass_model))
    settings = BaselineSettings(hw=resolve_hw(args.hw), tail=args.tail, mass_model=mass_model)
    try:
        estimate = estimate_baseline(source.pixels, source.focal_px, source.record.altitude_m,
                                     settings, _error_model(args, source, calibration),
                                     args.mc,
                                     np.random.default_rng(args.seed))
    except ValueError as exc:
        raise InputError(f"{named}: {exc}") from exc
    result = result_record(source, estimate, input_name=str(named), seed=args.seed)
    result_figures({name: result[name] for name in ("length_m", "volume_m3", "mass_kg")},
                   f"{named}")
    print(format_report(named, source, estimate, result))
    out_dir = args.out if args.out is not None else named.parent
    for path in write_exports(out_dir / named.stem, source, estimate, result,
                              args.mmx_version):
        print(f"wrote {path}" + (f" (MorphoMetriX v{args.mmx_version})"
                                 if path.name.endswith("_mmx.csv") else ""))
    if source.image_width_px is not None:  # an annotation knows Xcertainty's Iw and Sw
        image = source.record.image_id
        table = out_dir / f"{named.stem}_xcertainty.csv"
        write_wide_csv(table, [observation_row(source, args.subject or image, image,
                                               source.uas, None)])
        print(f"wrote {table}")
    return 0


def _check_options(args: argparse.Namespace) -> None:
    """InputError for option values outside their range, and for an output folder that is
    a file."""
    if args.mc < 0 or args.mc == 1:
        raise InputError(f"--mc must be 0 (no Monte Carlo) or at least 2, got {args.mc}")
    count(args.seed, 0, "--seed")
    if args.altitude_m is not None:
        in_range(args.altitude_m, ALTITUDE_M, "--altitude-m")
    for option in ("digitisation_sd_px", "altitude_sd_fraction", "focal_sd_fraction"):
        value = getattr(args, option)
        if value is not None:
            at_least(value, 0.0, f"--{option.replace('_', '-')}")
    if args.out is not None:
        check_output_folder(args.out, "--out ")
    for value, limits, option in ((args.sensor_width_mm, SENSOR_WIDTH_MM, "--sensor-width-mm"),
                                  (args.focal_mm, FOCAL_MM, "--focal-mm")):
        if value is not None:
            in_range(value, limits, option)
    if args.frame is not None:
        count(args.frame, 0, "--frame")
    if args.input is None:
        _check_mask_alone(args)
        return
    given = [name for name in MASK_ONLY_OPTIONS if getattr(args, name) is not None]
    if given:
        raise InputError(f"--{given[0].replace('_', '-')} is for --from-mask without an "
                         f"input file (the file has its own)")
    if args.length_name is not None and args.input.suffix.lower() == ".json":
        raise InputError("--length-name is for MorphoMetriX files (.csv)")


def _check_mask_alone(args: argparse.Namespace) -> None:
    """InputError unless a mask without an annotation comes with its altitude and camera."""
    if args.from_mask is None:
        raise InputError("give an annotation (.json), a MorphoMetriX file (.csv) or "
                         "--from-mask MASKS")
    if args.altitude_m is None:
        raise InputError("--from-mask without an annotation needs --altitude-m")
    given = (args.camera is not None, args.sensor_width_mm is not None, args.focal_mm is not None)
    if given not in ((True, False, False), (False, True, True)):
        raise InputError("--from-mask without an annotation needs its camera: --camera PRESET "
                         "or both --sensor-width-mm and --focal-mm")
    if args.length_name is not None:
        raise InputError("--length-name is for MorphoMetriX files (.csv)")


def _check_body(source: MeasureInput, where: Path) -> None:
    """InputError naming the input when its length or widths, in metres at its altitude, are
    implausible."""
    m_per_px = source.record.altitude_m / source.focal_px
    body_measurements(source.pixels.length_px * m_per_px,
                      (source.pixels.widths_px * m_per_px).tolist(), str(where))


def _from_annotation(args: argparse.Namespace) -> MeasureInput:
    """An annotation file with the altitude options applied (widths from a mask, the clicks
    through a lens model, if asked)."""
    doc = read_annotation_json(args.input)
    if args.altitude_m is not None or args.altitude_source is not None:
        calibration = doc.calibration
        doc = replace(doc, calibration=replace(
            calibration, altitude_m=args.altitude_m or calibration.altitude_m,
            altitude_source=args.altitude_source or calibration.altitude_source))
    notes = []
    if args.from_mask is not None:
        doc = with_mask_widths(doc, annotated_frame_mask(args.from_mask, doc))
        notes.append(f"widths from the mask {args.from_mask}")
    return _measured_annotation(args, doc, args.input, notes)


def _from_mask_alone(args: argparse.Namespace) -> MeasureInput:
    """The midline and widths a mask suggests (mask_midline.annotation_from_mask, as the batch
    measures), with the camera and altitude of the options."""
    track = read_masks(args.from_mask)
    frame_idx = _mask_frame(track, args.frame, args.from_mask)
    try:
        annotation = annotation_from_mask(track.mask(frame_idx), frame_idx)
    except ValueError as exc:
        raise InputError(f"{args.from_mask}, frame {frame_idx}: {exc}") from None
    camera = _mask_camera(args, track)
    calibration = Calibration(camera, args.camera, args.altitude_m,
                              args.altitude_source or MASK_ALTITUDE_SOURCE)
    doc = AnnotationFile(annotation, calibration, media_path=str(args.from_mask),
                         notes=MASK_NOTE)
    return _measured_annotation(args, doc, args.from_mask, [MASK_NOTE])


def _mask_frame(track: MaskTrack, frame_idx: int | None, where: Path) -> int:
    """``frame_idx`` if the mask shows the animal there, else (None) the frame where the mask
    is largest; InputError naming ``where`` otherwise."""
    if frame_idx is None:
        visible = np.flatnonzero(track.is_visible).tolist()
        if not visible:
            raise InputError(f"{where}: no animal in any mask")
        return max(visible, key=lambda f: int(track.mask(f).sum()))
    if not (frame_idx < track.num_frames and track.is_visible[frame_idx]):
        raise InputError(f"{where}: no animal in the mask of frame {frame_idx} "
                         f"({track.num_frames} frames)")
    return frame_idx


def _mask_camera(args: argparse.Namespace, track: MaskTrack) -> CameraPreset:
    """The camera of --camera (at its own frame size, which must be the mask's) or of
    --sensor-width-mm and --focal-mm at the mask's size."""
    if args.camera is None:
        return CameraPreset(name="explicit", description="camera values of the command line",
                            focal_mm=args.focal_mm, sensor_width_mm=args.sensor_width_mm,
                            image_width_px=track.width_px, image_height_px=track.height_px,
                            source="command line", approximate=False)
    preset = get_preset(args.camera)
    mismatch = preset_resolution_mismatch(preset, track.width_px, track.height_px)
    if mismatch is not None:
        raise InputError(f"{args.from_mask}: {mismatch}")
    return preset


def _measured_annotation(args: argparse.Namespace, doc: AnnotationFile, where: Path,
                         notes: list[str]) -> MeasureInput:
    """An annotation's measurements through the lens model of --lens or of its preset."""
    preset = doc.calibration.preset_name
    lens, lens_name = ((read_lens(args.lens), f"the lens model {args.lens.name}")
                       if args.lens is not None
                       else (preset_lens(preset), f"the lens model of {preset!r}"))
    try:
        doc, lens_notes, warnings = through_lens(doc, lens, lens_name)
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None
    source = measured_image_from_annotation(doc, image_id=default_image_id(doc, where),
                                            notes=notes + lens_notes)
    return replace(source, warnings=tuple(warnings))


def _from_morphometrix(args: argparse.Namespace) -> MeasureInput:
    """A MorphoMetriX CSV with the altitude options applied."""
    for option, value in (("--from-mask", args.from_mask), ("--lens", args.lens)):
        if value is not None:
            raise InputError(f"{option} needs an annotation (.json) with its clicks")
    source = measured_image_from_morphometrix(args.input, altitude_m=args.altitude_m,
                                              altitude_source=args.altitude_source,
                                              length_name=args.length_name)
    if args.altitude_source is None:
        source = replace(source, notes=[*source.notes,
                                        "set the altitude source with --altitude-source"])
    return source


def _error_model(args: argparse.Namespace, source: MeasureInput,
                 calibration: AltitudeCalibration | None) -> ErrorModel:
    """Defaults by altitude source and camera, the altitude's from a calibration, overridden
    by the options given. A calibration's line also absorbed the camera's scale, so the
    focal length's own error is then left out unless asked for."""
    overrides = ({} if calibration is None
                 else calibration.error_overrides(source.recorded_altitude_m))
    overrides |= {name: getattr(args, name) for name in
                  ("altitude_sd_fraction", "focal_sd_fraction", "digitisation_sd_px")
                  if getattr(args, name) is not None}
    return default_error_model(source.altitude_source, source.is_camera_approximate,
                               **overrides)


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
