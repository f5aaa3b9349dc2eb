"""Make a synthetic drone clip of a dolphin with known truth.

  dolphinfit synth OUT_DIR [--seed N] [--width-px W --height-px H] [--fps F] [--duration-s S]
                   [--altitude-m M] [--length-m M] [--sea-state 0..1] [--dive-depth-m M] …
                   [--water green|blue|sandy|murky] [--colouration dark|light_grey]
                   [--glitter 0..1] [--wet-specular X] [--splash 0..1] [--turn-flex X]
                   [--companion-offset-m M] [--seabed-depth-m M] [--hw-table PRESET]
                   [--section-exponent N] …
                   [--no-profile-warp] [--finer-mesh] [--no-scattering] [--no-refraction]
                   [--no-ripples] [--no-glints] [--no-compression] [--config FILE.json]

Writes OUT_DIR/clip.mp4 (clip.mkv, lossless, with --no-compression), OUT_DIR/masks/%06d.png,
OUT_DIR/parts.npz (flukes and rostrum regions per frame), OUT_DIR/altitude.csv
(frame,time_s,altitude_m), OUT_DIR/clip.SRT (DJI style; rel_alt is altitude minus the launch
height) and OUT_DIR/truth.json (volume, length, mass, BCI, shape and every frame's pose and
seed point). Same options and seed, same clip. Angles are in degrees, lengths in metres; every
option of the clip configuration has a flag (see --help); --water sets the water options from
a preset, and the options given beside it win.
"""

import argparse
from dataclasses import fields, replace
from pathlib import Path

from dolphinfit.app.progress import terminal_progress
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.io.output_paths import check_output_folder
from dolphinfit.core.synth.clip import make_clip
from dolphinfit.core.synth.config import COLOURATIONS, Effects, SynthConfig
from dolphinfit.core.synth.water import WATER_PRESETS, with_water


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """One flag per configuration field and effect."""
    parser.add_argument("out_dir", type=Path, help="folder to write the clip into")
    parser.add_argument("--config", type=Path, default=None,
                        help="a JSON configuration (e.g. a truth.json's 'config'); flags win")
    parser.add_argument("--water", choices=sorted(WATER_PRESETS), default=None,
                        help="water colour, clarity and seabed from a preset; flags win")
    for field in fields(SynthConfig):
        if field.name == "effects":
            continue
        flag = "--" + field.name.replace("_", "-")
        if field.name == "colouration":
            parser.add_argument(flag, dest=field.name, default=None,
                                metavar="|".join(COLOURATIONS))
            continue
        parser.add_argument(flag, dest=field.name, type=_parser_for(field.type), default=None,
                            metavar=_metavar(field.type))
    for field in fields(Effects):
        name = field.name.replace("_", "-")
        parser.add_argument(f"--{name}", dest=f"effect_{field.name}", action="store_true",
                            default=None)
        parser.add_argument(f"--no-{name}", dest=f"effect_{field.name}", action="store_false")


def run(args: argparse.Namespace) -> int:
    """Build the configuration and render the clip with a progress line."""
    check_output_folder(args.out_dir)
    config = _config(args)
    files = make_clip(config, args.out_dir, progress=terminal_progress())
    print(f"wrote {files.video}, {config.num_frames} masks, {files.altitude_csv.name}, "
          f"{files.srt.name}, {files.truth_json.name} in {args.out_dir}")
    return 0


def _config(args: argparse.Namespace) -> SynthConfig:
    config = SynthConfig()
    if args.config is not None:
        data = read_json(args.config, "the configuration")
        try:
            config = SynthConfig.from_json(data.get("config", data) if isinstance(data, dict)
                                           else data)
        except InputError as exc:
            raise InputError(f"{args.config}: {exc}") from None
    if args.water is not None:
        config = with_water(config, args.water)
    options = {f.name: getattr(args, f.name) for f in fields(SynthConfig)
               if f.name != "effects" and getattr(args, f.name) is not None}
    effects = {f.name: getattr(args, f"effect_{f.name}") for f in fields(Effects)
               if getattr(args, f"effect_{f.name}") is not None}
    return replace(config, **options, effects=replace(config.effects, **effects))


def _parser_for(annotation):
    text = str(annotation)
    if "tuple" in text:
        return _triple
    if "str" in text:
        return str
    if "int" in text and "float" not in text:
        return int
    return float


def _metavar(annotation) -> str:
    text = str(annotation)
    if "str" in text:
        return "NAME"
    return "R,G,B" if "tuple" in text else ("N" if text == "int" else "X")


def _triple(text: str) -> tuple[float, float, float]:
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 3:
        raise argparse.ArgumentTypeError(f"expected three comma-separated numbers, got {text!r}")
    return values
