"""Calibrate the altimeter from an object of known length photographed at several altitudes.

  dolphinfit calibrate altitude TABLE --out CAL.json [--object-length M]
                     [--camera PRESET | --focal-mm F --sensor-width-mm S --image-width W]
                     [--altimeter barometer|laser] [--drone NAME] [--plot PNG] [--json]

TABLE (.csv, .xlsx or .rda) holds one row per image of the object: its length in pixels and the
recorded altitude, in our columns (image, altitude_m, pixel_length), MedidoR's calibration
sheet or Xcertainty's calibration tables. The object's length and the camera come from the
options or from the table's own columns; where both say, they must agree. The fit is the
straight line from recorded to true altitude (offset and scale, with 95 % intervals) that
MedidoR and CollatriX use; Xcertainty's bias-only estimate is printed beside it. CAL.json goes
to `dolphinfit measure`, `fit` and `batch` with --altitude-calibration: altitudes are corrected
and the intervals take the calibration's spread as the altitude's error.
"""

import argparse
import json
from pathlib import Path

from core.camera_presets import get_preset
from core.errors import InputError
from core.io.calibration_table import ALTIMETERS, read_calibration_table
from core.io.output_paths import check_output_file
from core.measure.altitude_calibration import (
    AltitudeCalibration,
    CalibrationCamera,
    fit_altitude_calibration,
    write_altitude_calibration,
)

CAMERA_OPTIONS = ("focal_mm", "sensor_width_mm", "image_width")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``altitude`` action and its options."""
    actions = parser.add_subparsers(dest="calibrate_action", required=True, metavar="ACTION")
    altitude = actions.add_parser("altitude", help="fit recorded → true altitude from an "
                                  "object of known length")
    altitude.add_argument("table", type=Path, help="the object's pixel lengths and recorded "
                          "altitudes (.csv, .xlsx, .rda)")
    altitude.add_argument("--out", type=Path, required=True, metavar="CAL.json",
                          help="where to write the calibration")
    altitude.add_argument("--object-length", type=float, default=None, metavar="M",
                          help="the object's true length, metres (else the table's)")
    altitude.add_argument("--camera", default=None, metavar="PRESET",
                          help="the camera preset the images were taken with")
    altitude.add_argument("--focal-mm", type=float, default=None,
                          help="real focal length, mm (else the table's)")
    altitude.add_argument("--sensor-width-mm", type=float, default=None,
                          help="sensor width read in the images' mode, mm")
    altitude.add_argument("--image-width", type=int, default=None, metavar="PX",
                          help="image width, px")
    altitude.add_argument("--altimeter", choices=ALTIMETERS, default=None,
                          help="which altitudes, where the table has barometer and laser")
    altitude.add_argument("--drone", default=None, help="whose shots, where the table has "
                          "several drones")
    altitude.add_argument("--plot", type=Path, default=None, metavar="PNG",
                          help="also draw the shots and the line")
    altitude.add_argument("--json", action="store_true", dest="as_json",
                          help="print the calibration as JSON instead of a summary")
    altitude.set_defaults(calibrate_run=run_altitude)


def run(args: argparse.Namespace) -> int:
    """Dispatch to the chosen action."""
    return args.calibrate_run(args)


def _camera(args: argparse.Namespace) -> CalibrationCamera | None:
    """The camera the options name, or None to take the table's."""
    given = [name for name in CAMERA_OPTIONS if getattr(args, name) is not None]
    if args.camera is not None:
        if given:
            raise InputError(f"give --camera or --{given[0].replace('_', '-')}, not both")
        preset = get_preset(args.camera)
        return CalibrationCamera(preset.focal_mm, preset.sensor_width_mm, preset.image_width_px)
    if not given:
        return None
    if len(given) < len(CAMERA_OPTIONS):
        missing = [f"--{name.replace('_', '-')}" for name in CAMERA_OPTIONS if name not in given]
        raise InputError(f"give {', '.join(missing)} too (or --camera PRESET)")
    return CalibrationCamera(args.focal_mm, args.sensor_width_mm, args.image_width)


def summary(calibration: AltitudeCalibration) -> str:
    """What was fitted, in a few lines a user can check."""
    c = calibration
    low, high = c.recorded_range_m
    lines = [
        f"{c.source}: {c.num_shots} shots of a {c.object_length_m:g} m object, "
        f"{c.drone or 'drone not named'}, altitudes from {c.altimeter} ({low:g}–{high:g} m), "
        f"{c.camera.text()}",
        f"true altitude = {c.intercept_m:+.3f} m + {c.slope:.4f} × recorded",
        f"  offset 95 % interval {c.intercept_ci_m[0]:+.3f} … {c.intercept_ci_m[1]:+.3f} m, "
        f"scale {c.slope_ci[0]:.4f} … {c.slope_ci[1]:.4f}",
        f"  spread about the line: {c.residual_sd_m:.3f} m, {100 * c.residual_sd_fraction:.2f} % "
        f"of the altitude (the altitude SD intervals will use)",
        f"Xcertainty's model (bias only, camera as stated): recorded − true = "
        f"{c.bias_only_m:+.3f} m, SD {c.bias_only_sd_m:.3f} m",
    ]
    if c.outliers:
        lines.append(f"check these shots, more than 3 SD off the line: {', '.join(c.outliers)}")
    return "\n".join(lines)


def run_altitude(args: argparse.Namespace) -> int:
    """Read the table, fit, write CAL.json (and the plot), print what was fitted."""
    check_output_file(args.out, "--out ")
    if args.plot is not None:
        check_output_file(args.plot, "--plot ")
    table = read_calibration_table(args.table, args.altimeter, args.drone)
    calibration = fit_altitude_calibration(table, args.object_length, _camera(args))
    write_altitude_calibration(calibration, args.out)
    if args.plot is not None:
        from core.measure.calibration_plot import save_altitude_calibration_plot

        save_altitude_calibration_plot(table, calibration, args.plot)
    print(json.dumps(calibration.to_json(), indent=2) if args.as_json else summary(calibration))
    return 0
