"""Fit the 3D dolphin model to a clip: metric shape, motion, volume, condition and mass.

  dolphinfit fit CLIP --altitude (METRES | FILE.csv | FILE.srt | LASER_LOG) [--launch-height M]
                 [--time-offset S]
                 [--masks DIR|VIDEO|NPZ] [--camera PRESET | --sensor-width-mm X --focal-mm Y]
                 [--start S] [--end S] [--fps N] [--out DIR] [--no-roi] [--refraction]
                 [--vertical-prior] [--hw PRESET|CSV|model] [--config FILE.json]
                 [--altitude-source laser|barometer|manual] [--altitude-calibration CAL.json]
                 [--outline-sd-px PX] [--lens LENS.json] [--device auto|cpu|cuda]

Without --masks the built-in tracker finds the dolphin by itself (automatic seed). Writes
DIR/result.json (volume_m3, length_m, mass_kg, bci, frames, timings, status, …), DIR/result.npz
(every fitted array; core.fit.result_io reads both back), DIR/rest_mesh.ply, DIR/posed/%06d.ply
(one per fitted frame), DIR/overlays/%06d.png (frame | mask | render) and DIR/interval.json
(the 95 % intervals below, with what they assumed). --fps sets how many
frames per second of video are fitted (default 5; at most 35 frames, so a window longer than
7 s is fitted at a lower rate, evenly spaced). --hw names the HW table whose height/width
ratios give the heights a camera above cannot see (as `dolphinfit measure --hw`; "model"
keeps the template's own). The figures print with their 95 % intervals
(core.measure.fit_uncertainty: altitude and camera error, the masks' outline, the hidden
heights); --altitude-source sets the altitude error (default: barometer for a DJI SRT, laser
for a laser log, manual for a number or an altitude CSV); --altitude-calibration corrects the
altitudes by a calibration of the clip's camera (`dolphinfit calibrate altitude`) and takes the
altitude error from its spread; --outline-sd-px how far the masks'
outline may lie off the animal's (default: the larger of 0.36 px at 1920 px wide, in
proportion to the width, and 0.35 × the blur of the animal's edge: measured on the bench
suite's clips). --lens (a `dolphinfit calibrate lens` file of the clip's video mode) undistorts
the frames and masks the fit sees; without one, a fit whose animal reaches past half-way to
the frame's corner is warned about. --device is where the fit and the tracker's edge network
compute: auto (the default) takes a CUDA GPU when the installed torch sees one, else the CPU;
the salient network always runs on the CPU. The result is the same wherever it ran, to float
rounding on a GPU.

The last line says the fit's status: "complete", or "unreliable" with the reasons its figures
cannot be trusted (too few frames, a poor fit, a partial body, too few pixels:
core.fit.reliability), also in result.json's status and reasons.

Exit codes: 0 the fit ran to its end (complete or unreliable); 2 bad input; 1 an internal
error, or a fit that ended early (status "diverged": the loss turned non-finite; "cancelled"
comes only from callers of core.fit with a cancel event): its best state is still written,
with the reason in result.json's status_message and on stderr, because its figures are not a
complete fit's.
"""

import argparse
import sys
from dataclasses import replace
from pathlib import Path

from dolphinfit.app.commands.altitude_options import add_altitude_offsets, check_altitude_offsets
from dolphinfit.app.commands.device_option import add_device_argument, chosen_device
from dolphinfit.app.progress import terminal_progress
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig, fit_hw_table
from dolphinfit.core.fit.interval import run_interval
from dolphinfit.core.fit.outputs import check_fit_folder, write_outputs
from dolphinfit.core.fit.pipeline import CameraChoice, FitRun, run_fit
from dolphinfit.core.fit.result import STATUS_UNRELIABLE, FitResult
from dolphinfit.core.io.json_file import read_json, write_json
from dolphinfit.core.measure.annotation import ALTITUDE_SOURCE_OF_KIND, ALTITUDE_SOURCES
from dolphinfit.core.measure.fit_uncertainty import FitInterval
from dolphinfit.core.measure.lens import read_lens
from dolphinfit.core.measure.preset_lens import preset_lens
from dolphinfit.core.io.video import open_clip
from dolphinfit.core.model.hw_spec import resolve_hw
from dolphinfit.core.measure.altitude_calibration import (
    AltitudeCalibration, read_altitude_calibration,
)
from dolphinfit.core.measure.records import default_error_model
from dolphinfit.core.measure.uncertainty import ErrorModel
from dolphinfit.core.limits import (
    ALTITUDE_M, FOCAL_MM, FPS, MASK_OUTLINE_SD_PX, SENSOR_WIDTH_MM, in_range,
    result_figures, time_window,
)
from dolphinfit.core.model.template import load_template
from dolphinfit.core.project.comparison import method_value


INTERVAL_JSON = "interval.json"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``fit``."""
    parser.add_argument("clip", type=Path, help="the drone clip")
    parser.add_argument("--altitude", required=True,
                        help="metres above the water, or an altitude CSV, DJI SRT or laser log")
    add_altitude_offsets(parser)
    parser.add_argument("--masks", type=Path, default=None,
                        help="mask PNG folder, mask video or .npz (default: the built-in tracker)")
    parser.add_argument("--camera", default=None, metavar="PRESET", help="camera preset name")
    parser.add_argument("--sensor-width-mm", type=float, default=None)
    parser.add_argument("--focal-mm", type=float, default=None)
    parser.add_argument("--start", type=float, default=None, metavar="S", help="start time, s")
    parser.add_argument("--end", type=float, default=None, metavar="S", help="end time, s")
    parser.add_argument("--fps", type=float, default=None,
                        help=f"frames fitted per second (at most {FitConfig().max_frames} "
                             "frames in all)")
    parser.add_argument("--out", type=Path, default=Path("out/fit"), help="output folder")
    parser.add_argument("--no-roi", action="store_true",
                        help="whole frames at 720 px wide, as the paper (default: native crops)")
    parser.add_argument("--refraction", action="store_true",
                        help="model flat-water refraction of submerged parts (off by default)")
    parser.add_argument("--vertical-prior", action="store_true",
                        help="the paper's v_surf/v_dive depth nudge")
    parser.add_argument("--hw", default=None, metavar="PRESET|CSV|model",
                        help="HW table for the heights a top view cannot see (default: the "
                             "configuration's, else the default preset); model: the "
                             "template's own")
    parser.add_argument("--config", type=Path, default=None, help="a FitConfig JSON")
    parser.add_argument("--altitude-calibration", type=Path, default=None, metavar="CAL.json",
                        help="correct the altitudes with a calibration from `dolphinfit "
                             "calibrate altitude` (its spread becomes the altitude's SD)")
    parser.add_argument("--altitude-source", choices=ALTITUDE_SOURCES, default=None,
                        help="what measured the altitude, for the intervals (default: "
                             "barometer for an SRT, laser for a laser log, else manual)")
    parser.add_argument("--outline-sd-px", type=float, default=None, metavar="PX",
                        help="one SD of the masks' outline offset in the clip's pixels, for "
                             "the intervals (default: the larger of 0.36 px at 1920 px wide, "
                             "in proportion to the width, and 0.35 × the edge's blur index; "
                             "0: masks taken as exact)")
    parser.add_argument("--lens", type=Path, default=None, metavar="LENS.json",
                        help="fit through this lens model (`dolphinfit calibrate lens`, same "
                             "video mode; default: the --camera preset's, if it keeps one)")
    add_device_argument(parser, "where the fit and, without --masks, the tracker's edge "
                                "network compute (its salient network runs on the CPU)")


def fit_config(args: argparse.Namespace) -> FitConfig:
    """The configuration from --config and the flags (flags win)."""
    config = FitConfig()
    if args.config is not None:
        data = read_json(args.config, "the fit configuration")
        try:
            config = FitConfig.from_json(data)
        except InputError as exc:
            raise InputError(f"{args.config}: {exc}") from None
    changes = {"use_roi": config.use_roi and not args.no_roi,
               "use_refraction": config.use_refraction or args.refraction,
               "use_vertical_prior": config.use_vertical_prior or args.vertical_prior,
               "start_s": args.start if args.start is not None else config.start_s,
               "end_s": args.end if args.end is not None else config.end_s}
    if args.fps is not None:
        changes["fps"] = args.fps
    if args.hw is not None:
        changes["hw_table"] = fit_hw_table(args.hw)
    config = replace(config, **changes)
    if config.hw_table is not None:  # a table the fit could not read, named before any work
        try:
            resolve_hw(config.hw_table)
        except InputError as exc:
            where = "--hw" if args.hw is not None else args.config or "fit option hw_table"
            raise InputError(f"{where}: {exc}") from None
    return config


def check_options(args: argparse.Namespace) -> None:
    """InputError naming the option whose value is outside its plausible range."""
    check_altitude_offsets(args)
    if args.outline_sd_px is not None:
        in_range(args.outline_sd_px, MASK_OUTLINE_SD_PX, "--outline-sd-px")
    for value, limits, option in ((args.sensor_width_mm, SENSOR_WIDTH_MM, "--sensor-width-mm"),
                                  (args.focal_mm, FOCAL_MM, "--focal-mm"),
                                  (args.fps, FPS, "--fps")):
        if value is not None:
            in_range(value, limits, option)
    time_window(args.start, args.end, "--start", "--end")


def run(args: argparse.Namespace) -> int:
    """Fit, write the outputs, print the figures."""
    check_options(args)
    check_fit_folder(args.out, "--out ")
    camera = CameraChoice(args.camera, args.sensor_width_mm, args.focal_mm)
    altitude = args.altitude
    if not Path(altitude).exists():
        try:
            altitude = in_range(float(altitude), ALTITUDE_M, "--altitude")
        except ValueError:
            raise InputError(f"--altitude {altitude!r}: neither a number of metres nor a file")
    calibration = (None if args.altitude_calibration is None
                   else read_altitude_calibration(args.altitude_calibration))
    lens, lens_name = ((read_lens(args.lens), f"--lens {args.lens}") if args.lens is not None
                       else (preset_lens(args.camera), f"the lens model of {args.camera!r}"))
    if lens is not None:
        clip = open_clip(args.clip)
        lens.check_image_size(clip.width_px, clip.height_px, lens_name)
        print(f"fitting through {lens_name}", file=sys.stderr)
    config, device = fit_config(args), chosen_device(args)
    fit_run = run_fit(args.clip, altitude, args.masks, camera, config,
                      args.launch_height, progress=terminal_progress(),
                      time_offset_s=args.time_offset, altitude_calibration=calibration,
                      lens=lens, device=device)
    return report(fit_run, args.out, camera, args.altitude_source, args.outline_sd_px,
                  calibration)


def _interval_lines(result: FitResult, interval: FitInterval, altitude_source: str) -> list[str]:
    """The figures with their 95 % intervals, and what the intervals assume."""
    def shown(key: str, fmt: str) -> str:
        return method_value(getattr(result, key), getattr(interval, key)).text(fmt)

    return [f"length {shown('length_m', '.3f')} m   volume {shown('volume_m3', '.4f')} m³",
            f"BCI {shown('bci', '+.3f')}   mass {shown('mass_kg', '.1f')} kg",
            f"(95 % intervals: altitude from the {altitude_source}, masks' outline "
            f"±{interval.outline_sd_px:.2g} px, the HW table's heights)"]


def fit_error_model(fit_run: FitRun, source: str, camera: CameraChoice,
                    calibration: AltitudeCalibration | None) -> ErrorModel:
    """The defaults of ``source`` and the camera; with a calibration (whose line absorbed
    the camera's scale) its spread at the fitted frames' median altitude instead."""
    if calibration is None:
        return default_error_model(source, camera.is_approximate(fit_run.clip))
    recorded = calibration.recorded_altitude(float(fit_run.data.camera.altitude_m.median()))
    return default_error_model(source, camera.is_approximate(fit_run.clip),
                               **calibration.error_overrides(recorded))


def report(fit_run: FitRun, out_dir: Path, camera: CameraChoice,
           altitude_source: str | None = None, outline_sd_px: float | None = None,
           calibration: AltitudeCalibration | None = None) -> int:
    """Write the outputs, print the figures with their intervals (``altitude_source``: by
    default the one that goes with the altitude file; ``calibration``: the altitudes' own,
    if they were calibrated) and the warnings; the exit code (module docstring).

    A completed fit with an implausible length, or a volume or mass that is not positive, is
    refused (exit 2) and not written."""
    result = fit_run.result
    if result.finished:
        result_figures({"length_m": result.length_m, "volume_m3": result.volume_m3,
                        "mass_kg": result.mass_kg},
                       f"fit of {fit_run.clip.path.name} (check the altitude and the camera)")
    written = write_outputs(result, fit_run.data, load_template(), out_dir)
    print(f"fitted {len(result.frame_idx)} frames of {fit_run.clip.path.name} "
          f"in {result.timings_s.get('total', 0.0):.0f} s, mean IoU {result.iou.mean():.3f}")
    print(f"masks: {fit_run.masks.source}")
    if result.volume_m3 > 0 and result.length_m > 0:
        source = altitude_source or ALTITUDE_SOURCE_OF_KIND.get(
            fit_run.telemetry.source.kind, "manual")
        interval = run_interval(fit_run, fit_error_model(fit_run, source, camera, calibration),
                                outline_sd_px)
        calibrated = {} if calibration is None else {"altitude_calibration": calibration.source}
        write_json(out_dir / INTERVAL_JSON,
                   {"altitude_source": source, **calibrated, **interval.to_json()})
        written.append(out_dir / INTERVAL_JSON)
        print("\n".join(_interval_lines(result, interval, source)))
    else:
        print(f"length {result.length_m:.3f} m   volume {result.volume_m3:.4f} m³   "
              f"BCI {result.bci:+.3f}   mass {result.mass_kg:.1f} kg")
    for warning in fit_run.data.warnings + tuple(w for w in result.warnings
                                                 if w not in fit_run.data.warnings):
        print(f"warning: {warning}")
    print(f"wrote {len(written)} file{'s' if len(written) != 1 else ''} to {out_dir}")
    if result.finished:
        print(status_line(result))
        return 0
    print(f"dolphinfit: error: fit {result.status}: {result.status_message}",
          file=sys.stderr)
    return 1


def status_line(result: FitResult) -> str:
    """The command's last line: the fit's status, and why it cannot be trusted where it
    cannot."""
    if result.status == STATUS_UNRELIABLE:
        return f"status: unreliable: {result.status_message}"
    return f"status: {result.status}"
