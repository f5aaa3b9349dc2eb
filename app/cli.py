"""The ``dolphinfit`` command line: argparse subcommands over ``core`` functions.

Exit codes (DESIGN.md §8): 0 success, 2 bad input (the message names the file and the
problem), 1 internal error.
"""

import argparse
import sys
from collections.abc import Sequence
from types import ModuleType

from app.commands import bench, camera, demo, fit, masks, measure, synth, telemetry, template
from core.errors import InputError

SUBCOMMANDS: dict[str, ModuleType] = {
    "template": template,
    "camera": camera,
    "measure": measure,
    "synth": synth,
    "telemetry": telemetry,
    "masks": masks,
    "bench": bench,
    "fit": fit,
    "demo": demo,
}


def build_parser() -> argparse.ArgumentParser:
    """The full parser; each subcommand module's docstring is its help text."""
    parser = argparse.ArgumentParser(
        prog="dolphinfit",
        description="Size, body condition and mass of dolphins from nadir drone video.",
    )
    parser.add_argument(
        "--threads", type=int, default=None,
        help="torch CPU threads (default: $DOLPHINFIT_THREADS or 2)",
    )
    subparsers = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, module in SUBCOMMANDS.items():
        doc = (module.__doc__ or "").strip()
        sub = subparsers.add_parser(
            name, help=doc.splitlines()[0] if doc else None, description=doc,
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        module.add_arguments(sub)
        sub.set_defaults(run=module.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Parse ``argv``, run the subcommand and return its exit code."""
    from core.runtime import configure_threads

    args = build_parser().parse_args(argv)
    try:
        configure_threads(args.threads)
        return args.run(args)
    except InputError as exc:
        print(f"dolphinfit: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
