"""The ``dolphinfit`` command line: argparse subcommands over ``core`` functions.

Exit codes (DESIGN.md §8): 0 success, 2 bad input (the message names the file and the
problem), 1 internal error.

Only the chosen subcommand's module is imported, so ``dolphinfit gui`` opens without loading
the fitting stack (torch) that other commands need.
"""

import argparse
import importlib
import sys
import traceback
from collections.abc import Sequence
from types import ModuleType

from dolphinfit.core.crash_report import installed_version, write_crash_report
from dolphinfit.core.errors import InputError
from dolphinfit.core.limits import count

SUBCOMMANDS: dict[str, str] = {  # name → the first line of its module's docstring
    "gui": "The desktop app: measure length and widths by hand, see volume, BCI and mass at once.",
    "template": "Build, inspect and export the procedural dolphin template.",
    "camera": "Camera presets: list them, show one's geometry on the water, add your own.",
    "measure": "Elliptical baseline: length, volume, BCI and mass with 95 % intervals, and "
               "the exports.",
    "synth": "Make a synthetic drone clip of a dolphin with known truth.",
    "telemetry": "Read an altitude source, summarise it and optionally write it as CSV.",
    "calibrate": "Calibrate the altimeter from an object of known length, and the lens from "
                 "a checkerboard.",
    "scan": "Find the animals in clips and the frames worth measuring each of them in.",
    "masks": "Track the dolphin through a clip (or find it in a still) and write its masks.",
    "bench": "Measure speed and accuracy side by side in one run.",
    "fit": "Fit the 3D dolphin model to a clip: metric shape, motion, volume, condition and "
           "mass.",
    "demo": "The headless main job: fit the bundled sample clip and compare with its known "
            "truth.",
    "batch": "Fit and measure many clips and animals as Dask tasks, resumably, into one "
             "summary table.",
    "train": "Train the project's own networks again from synthetic clips, reproducibly.",
}


def command_module(name: str) -> ModuleType:
    """The module of subcommand ``name`` (``app/commands/NAME.py``)."""
    return importlib.import_module(f"dolphinfit.app.commands.{name}")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser with every subcommand; only ``command``'s options are added (all of them
    when None), so only its module is imported."""
    parser = argparse.ArgumentParser(
        prog="dolphinfit",
        description="Size, body condition and mass of dolphins from nadir drone video.",
    )
    parser.add_argument("--version", action="version",
                        version=f"dolphinfit {installed_version('dolphinfit') or 'not installed'}")
    parser.add_argument(
        "--threads", type=int, default=None,
        help="torch CPU threads (default: $DOLPHINFIT_THREADS or 2)",
    )
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, summary in SUBCOMMANDS.items():
        summary = summary.replace("%", "%%")  # argparse formats help text with %
        if command not in (None, name):
            subparsers.add_parser(name, help=summary)
            continue
        module = command_module(name)
        sub = subparsers.add_parser(
            name, help=summary, description=(module.__doc__ or "").strip(),
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        module.add_arguments(sub)
        sub.set_defaults(run=module.run, module=module)
    return parser


INTERRUPTED = 130   # 128 + SIGINT, as shells report a Ctrl-C


def main(argv: Sequence[str] | None = None) -> int:
    """Parse ``argv``, run the subcommand and return its exit code."""
    argv = list(sys.argv[1:] if argv is None else argv)
    command = next((arg for arg in argv if arg in SUBCOMMANDS), None)
    args = build_parser(command).parse_args(argv)
    try:
        if args.threads is not None:
            count(args.threads, 1, "--threads")
        if getattr(args.module, "LOADS_TORCH", True):
            from dolphinfit.core.runtime import configure_threads
            configure_threads(args.threads)
        return args.run(args)
    except InputError as exc:
        print(f"dolphinfit: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C: no traceback, the exit code shells expect
        print(f"dolphinfit {args.command}: interrupted; every file is written whole or not at "
              "all, so those finished before the interrupt are kept and none is half-written",
              file=sys.stderr)
        return INTERRUPTED
    except Exception as exc:  # an internal error: the user gets a report to send, not a trace
        return internal_error(exc, args.command)


def internal_error(error: Exception, command: str) -> int:
    """Write a crash report of ``error`` (core.crash_report), say where it is and what to
    do; exit code 1. Where even the report cannot be written, the traceback is printed."""
    try:
        path = write_crash_report(error, f"dolphinfit {command}")
    except OSError as exc:
        traceback.print_exception(error)
        print(f"dolphinfit {command}: internal error: {error} (the crash report could not be "
              f"written: {exc})", file=sys.stderr)
        return 1
    print(f"dolphinfit {command}: internal error: {error}\nThis is a fault of dolphinfit, not "
          f"of your input. The crash report is {path}: please attach it to a bug report with "
          f"the command you ran.", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
