"""Camera presets: list them, show one's geometry on the water, add your own.

`camera lens PRESET LENS.json` keeps a lens model with a preset: its measurements and fits
then go through it (core/measure/preset_lens.py).

Bundled presets live in resources/cameras.json. Your own are saved to
$DOLPHINFIT_CONFIG_DIR/cameras.json (else $XDG_CONFIG_HOME/dolphinfit/cameras.json) and
override bundled presets of the same name. A preset names the real focal length and the sensor
width that the video mode reads; the SRT file's 35 mm-equivalent focal_len never gives scale.
"""

import argparse
import json
import math
from dataclasses import asdict
from pathlib import Path

from dolphinfit.core.camera_presets import (
    DEFAULT_PRESET,
    CameraPreset,
    get_preset,
    load_presets,
    save_user_preset,
)
from dolphinfit.core.errors import InputError
from dolphinfit.core.limits import ALTITUDE_M, FOCAL_MM, IMAGE_SIZE_PX, SENSOR_WIDTH_MM, in_range
from dolphinfit.core.measure.lens import read_lens
from dolphinfit.core.measure.preset_lens import preset_lens, preset_lens_path, store_preset_lens

REFERENCE_ALTITUDE_M = 20.0  # mid-range of the 15–25 m flights of DESIGN.md §1
CM_PER_M = 100.0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``list``, ``show`` and ``add`` actions and their options."""
    actions = parser.add_subparsers(dest="camera_action", required=True, metavar="ACTION")

    list_parser = actions.add_parser("list", help="list the camera presets")
    list_parser.add_argument("--json", action="store_true", dest="as_json",
                             help="print JSON instead of a table")
    list_parser.set_defaults(camera_run=run_list)

    show_parser = actions.add_parser("show", help="intrinsics, field of view and footprint")
    show_parser.add_argument("name", help="preset name (see `dolphinfit camera list`)")
    show_parser.add_argument("--altitude-m", type=float, default=REFERENCE_ALTITUDE_M,
                             help="camera height above the water, metres (default: %(default)s)")
    show_parser.set_defaults(camera_run=run_show)

    add_parser = actions.add_parser("add", help="save a user preset (overrides one of that name)")
    add_parser.add_argument("name", help="preset name")
    add_parser.add_argument("--sensor-width-mm", type=float, required=True,
                            help="width of the sensor area the video mode reads, mm")
    add_parser.add_argument("--focal-mm", type=float, required=True,
                            help="real (not 35 mm-equivalent) focal length, mm")
    add_parser.add_argument("--width-px", type=int, required=True, help="video frame width, px")
    add_parser.add_argument("--height-px", type=int, required=True, help="video frame height, px")
    add_parser.add_argument("--description", default="", help="free text")
    add_parser.add_argument("--source", default="entered with `dolphinfit camera add`",
                            help="where the values come from")
    add_parser.add_argument("--approximate", action="store_true",
                            help="mark the values as unverified")
    add_parser.set_defaults(camera_run=run_add)
    lens_parser = actions.add_parser(
        "lens", help="keep a lens model (`dolphinfit calibrate lens`) with a preset: its "
                     "measurements and fits then go through it")
    lens_parser.add_argument("name", help="preset name")
    lens_parser.add_argument("lens", type=Path, nargs="?", default=None, metavar="LENS.json",
                             help="the lens model, calibrated at the preset's image size")
    lens_parser.add_argument("--remove", action="store_true", help="forget the preset's lens")
    lens_parser.set_defaults(camera_run=run_lens)


def run(args: argparse.Namespace) -> int:
    """Dispatch to the chosen action."""
    return args.camera_run(args)


def preset_summary(preset: CameraPreset, altitude_m: float) -> dict[str, object]:
    """The preset's fields plus focal_px, fov_x_deg and gsd_m_per_px at ``altitude_m``."""
    intrinsics = preset.intrinsics()
    return {
        **asdict(preset),
        "focal_px": intrinsics.focal_px,
        "fov_x_deg": math.degrees(intrinsics.fov_x_rad),
        "altitude_m": altitude_m,
        "gsd_m_per_px": intrinsics.gsd_m_per_px(altitude_m),
    }


def _table(rows: list[list[str]]) -> str:
    """Left-aligned columns separated by two spaces."""
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]))]
    return "\n".join(
        "  ".join(cell.ljust(width) for cell, width in zip(row, widths)).rstrip() for row in rows
    )


def run_list(args: argparse.Namespace) -> int:
    """Print all presets, as a table or as JSON."""
    summaries = [preset_summary(p, REFERENCE_ALTITUDE_M) for p in load_presets().values()]
    if args.as_json:
        print(json.dumps({"default": DEFAULT_PRESET, "presets": summaries}, indent=2,
                         ensure_ascii=False))
        return 0
    rows = [["name", "resolution", "sensor_mm", "focal_mm", "fov_x",
             f"gsd@{REFERENCE_ALTITUDE_M:g}m", "approx", "source"]]
    for s in summaries:
        rows.append([
            s["name"] + (" *" if s["name"] == DEFAULT_PRESET else ""),
            f"{s['image_width_px']}x{s['image_height_px']}",
            f"{s['sensor_width_mm']:g}",
            f"{s['focal_mm']:g}",
            f"{s['fov_x_deg']:.1f}°",
            f"{s['gsd_m_per_px'] * CM_PER_M:.2f} cm/px",
            "yes" if s["approximate"] else "no",
            s["source"],
        ])
    print(_table(rows))
    print("* default")
    return 0


def run_show(args: argparse.Namespace) -> int:
    """Print one preset's intrinsics, field of view, GSD and footprint at an altitude."""
    in_range(args.altitude_m, ALTITUDE_M, "--altitude-m")
    preset = get_preset(args.name)
    k = preset.intrinsics()
    gsd_m_per_px = k.gsd_m_per_px(args.altitude_m)
    print(f"{preset.name}: {preset.description}")
    print(_table([
        ["image", f"{k.width_px} x {k.height_px} px"],
        ["sensor width", f"{preset.sensor_width_mm:g} mm"],
        ["focal length", f"{preset.focal_mm:g} mm = {k.focal_px:.2f} px"],
        ["principal point", f"({k.cx_px:.1f}, {k.cy_px:.1f}) px"],
        ["field of view", f"{math.degrees(k.fov_x_rad):.2f}° x {math.degrees(k.fov_y_rad):.2f}°"],
        ["altitude", f"{args.altitude_m:g} m"],
        ["GSD", f"{gsd_m_per_px * CM_PER_M:.3f} cm/px"],
        ["footprint", f"{k.width_px * gsd_m_per_px:.2f} x {k.height_px * gsd_m_per_px:.2f} m"],
        ["approximate", "yes" if preset.approximate else "no"],
        ["source", preset.source],
        ["lens model", str(preset_lens_path(preset.name)) if preset_lens(preset.name)
         else "none"],
    ]))
    return 0


def run_lens(args: argparse.Namespace) -> int:
    """Store (or with --remove, forget) a preset's lens model."""
    preset = get_preset(args.name)
    path = preset_lens_path(preset.name)
    if args.remove == (args.lens is not None):
        raise InputError("camera lens: give a LENS.json or --remove")
    if args.remove:
        existed = path.exists()
        path.unlink(missing_ok=True)
        print(f"{'removed' if existed else 'no'} lens model of {preset.name!r}"
              + (f" ({path})" if existed else ""))
        return 0
    stored = store_preset_lens(preset, read_lens(args.lens))
    print(f"lens model of {preset.name!r} kept in {stored}: its measurements and fits go "
          "through it")
    return 0


_ADD_OPTIONS = {  # CameraPreset field → the `camera add` option that sets it, its range
    "focal_mm": ("--focal-mm", FOCAL_MM),
    "sensor_width_mm": ("--sensor-width-mm", SENSOR_WIDTH_MM),
    "image_width_px": ("--width-px", IMAGE_SIZE_PX),
    "image_height_px": ("--height-px", IMAGE_SIZE_PX),
}


def run_add(args: argparse.Namespace) -> int:
    """Validate the options and save them as a user preset."""
    values = {"focal_mm": args.focal_mm, "sensor_width_mm": args.sensor_width_mm,
              "image_width_px": args.width_px, "image_height_px": args.height_px}
    for field, value in values.items():
        in_range(value, _ADD_OPTIONS[field][1], _ADD_OPTIONS[field][0])
    if not args.name.strip():
        raise InputError("camera add: the preset name must not be empty")
    preset = CameraPreset(name=args.name, description=args.description, source=args.source,
                          approximate=args.approximate, **values)
    is_replacing = preset.name in load_presets()
    path = save_user_preset(preset)
    print(f"{'replaced' if is_replacing else 'added'} camera preset {preset.name!r} in {path}")
    return 0
