"""Calibrate the altimeter from an object of known length, and the lens from a checkerboard.

  dolphinfit calibrate lens IMAGES…|VIDEO --board COLSxROWS --square-mm S --out LENS.json
                     [--every K] [--preset PRESET]
  dolphinfit calibrate altitude TABLE|PROJECT --out CAL.json [--object-length M]
                     [--camera PRESET | --focal-mm F --sensor-width-mm S --image-width W]
                     [--altimeter barometer|laser] [--drone NAME] [--plot PNG] [--json]

TABLE (.csv, .xlsx or .rda) holds one row per image of the object: its length in pixels and the
recorded altitude, in our columns (image, altitude_m, pixel_length), MedidoR's calibration
sheet or Xcertainty's calibration tables; or a project, whose calibration made in the app
(chosen with --drone where it has several) is fitted as it is. The object's length and the
camera come from the options or from the table's own columns; where both say, they must
agree. The fit is the straight line from recorded to true altitude (offset and scale, with
95 % intervals) that MedidoR and CollatriX use; Xcertainty's bias-only estimate is printed beside it. CAL.json goes
to `dolphinfit measure`, `fit` and `batch` with --altitude-calibration: altitudes are corrected
and the intervals take the calibration's spread as the altitude's error.

`lens` finds a printed checkerboard (--board: its inner corners, e.g. 9x6) in images, or in
every K-th frame of a video, and fits the lens's distortion with OpenCV (core/measure/lens.py);
fewer than 5 views or corners more than 1 px (RMS) from the fit are refused. LENS.json goes to
`dolphinfit measure --lens` (the clicks taken through it) and `fit --lens` (the frames and
masks undistorted); --preset also keeps it with a camera preset (`dolphinfit camera lens`),
whose measurements and fits then use it.
"""

import argparse
import json
from pathlib import Path

from dolphinfit.core.camera_presets import get_preset
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.calibration_table import ALTIMETERS, read_calibration_table
from dolphinfit.core.io.media import VIDEO_SUFFIXES
from dolphinfit.core.io.output_paths import check_output_file
from dolphinfit.core.project.project_file import PROJECT_SUFFIX
from dolphinfit.core.limits import count
from dolphinfit.core.measure.altitude_calibration import (
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
    altitude.add_argument("table", type=Path, metavar="TABLE|PROJECT",
                          help="the object's pixel lengths and recorded altitudes (.csv, "
                               ".xlsx, .rda), or a project whose calibration to fit")
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
                          "several drones; of a project, the calibration's name")
    altitude.add_argument("--plot", type=Path, default=None, metavar="PNG",
                          help="also draw the shots and the line")
    altitude.add_argument("--json", action="store_true", dest="as_json",
                          help="print the calibration as JSON instead of a summary")
    altitude.set_defaults(calibrate_run=run_altitude)

    lens = actions.add_parser("lens", help="the lens's distortion from images or a video of "
                              "a printed checkerboard")
    lens.add_argument("inputs", type=Path, nargs="+", metavar="IMAGES|VIDEO",
                      help="images of the board, a video of it or a folder of its frames")
    lens.add_argument("--board", required=True, metavar="COLSxROWS",
                      help="inner corners of the board, e.g. 9x6")
    lens.add_argument("--square-mm", type=float, required=True,
                      help="the side of one square, mm")
    lens.add_argument("--every", type=int, default=15, metavar="K",
                      help="of a video, every K-th frame (default 15)")
    lens.add_argument("--out", type=Path, required=True, metavar="LENS.json",
                      help="where to write the lens model")
    lens.add_argument("--preset", default=None, metavar="PRESET",
                      help="also keep it with this camera preset (`dolphinfit camera lens`)")
    lens.set_defaults(calibrate_run=run_lens)


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


def _project_calibration(args: argparse.Namespace):
    """The shots and fitted line of a project's calibration set (the one named by --drone,
    or its only one); the object and camera are the set's own."""
    from dolphinfit.core.project.calibrations import fitted_calibration
    from dolphinfit.core.project.project_file import read_project

    given = [option for option, value in (("--object-length", args.object_length),
                                          ("--camera", args.camera),
                                          ("--altimeter", args.altimeter))
             if value is not None] + [f"--{name.replace('_', '-')}" for name in CAMERA_OPTIONS
                                      if getattr(args, name) is not None]
    if given:
        raise InputError(f"{args.table}: a project's calibration carries its own object, "
                         f"camera and altimeter; drop {', '.join(given)}")
    project = read_project(args.table)
    names = [c.name for c in project.calibrations]
    if not names:
        raise InputError(f"{args.table}: the project has no altitude calibration (Clip → "
                         f"Altitude calibration… in the app)")
    if args.drone is None and len(names) > 1:
        raise InputError(f"{args.table}: {len(names)} calibrations ({', '.join(names)}); "
                         f"choose one with --drone")
    name = args.drone if args.drone is not None else names[0]
    if name not in names:
        raise InputError(f"{args.table}: no calibration {name!r}; it has {', '.join(names)}")
    calibration_set = project.calibration(name)
    return calibration_set.shots, fitted_calibration(calibration_set)


def run_altitude(args: argparse.Namespace) -> int:
    """Read the table, fit, write CAL.json (and the plot), print what was fitted."""
    check_output_file(args.out, "--out ")
    if args.plot is not None:
        check_output_file(args.plot, "--plot ")
    if args.table.suffix == PROJECT_SUFFIX:
        shots, calibration = _project_calibration(args)
    else:
        table = read_calibration_table(args.table, args.altimeter, args.drone)
        shots = table.shots
        calibration = fit_altitude_calibration(table, args.object_length, _camera(args))
    write_altitude_calibration(calibration, args.out)
    if args.plot is not None:
        from dolphinfit.core.measure.calibration_plot import save_altitude_calibration_plot

        save_altitude_calibration_plot(shots, calibration, args.plot)
    print(json.dumps(calibration.to_json(), indent=2) if args.as_json else summary(calibration))
    return 0


def _board(text: str) -> tuple[int, int]:
    try:
        columns, rows = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise InputError(f"--board {text!r}: expected the inner corners as COLSxROWS, e.g. 9x6") \
            from None
    return columns, rows


def _board_images(inputs: list[Path], every: int):
    """The images to look for the board in: each file, or every ``every``-th frame of one
    video or folder of frames."""
    from dolphinfit.core.io.image_file import read_image
    from dolphinfit.core.io.media import open_media

    if len(inputs) == 1 and (inputs[0].is_dir() or inputs[0].suffix.lower() in VIDEO_SUFFIXES):
        with open_media(inputs[0]) as frames:
            for _, rgb in frames.frames(range(0, len(frames), every)):
                yield rgb
        return
    for path in inputs:
        yield read_image(path)


def run_lens(args: argparse.Namespace) -> int:
    """Find the board, calibrate, write LENS.json, print what was fitted."""
    from dolphinfit.core.measure.lens import calibrate_lens, write_lens

    from dolphinfit.core.measure.preset_lens import store_preset_lens

    check_output_file(args.out, "--out ")
    count(args.every, 1, "--every")
    preset = None if args.preset is None else get_preset(args.preset)
    lens = calibrate_lens(_board_images(args.inputs, args.every), _board(args.board),
                          args.square_mm, ", ".join(p.name for p in args.inputs[:3])
                          + (" …" if len(args.inputs) > 3 else ""))
    write_lens(lens, args.out)
    k1, k2, p1, p2, _ = lens.distortion
    print(f"{lens.num_views} views of the board, {lens.width_px}×{lens.height_px} px: corners "
          f"{lens.rms_px:.3f} px (RMS) from the fitted lens\n"
          f"focal {lens.fx_px:.1f} × {lens.fy_px:.1f} px, centre ({lens.cx_px:.1f}, "
          f"{lens.cy_px:.1f}) px; k1 {k1:+.5f}, k2 {k2:+.5f}, p1 {p1:+.6f}, p2 {p2:+.6f}")
    if preset is not None:
        print(f"kept with camera preset {preset.name!r}: {store_preset_lens(preset, lens)}")
    return 0

