"""The two options that place an altitude file's readings on a clip, shared by the commands
that read one: the take-off point's height (relative SRT altitudes) and a laser log's time
offset."""

import argparse

from dolphinfit.core.limits import LAUNCH_HEIGHT_M, in_range, number


def add_altitude_offsets(parser: argparse.ArgumentParser) -> None:
    """``--launch-height`` and ``--time-offset``."""
    parser.add_argument("--launch-height", type=float, default=0.0, metavar="M",
                        help="take-off point's height above the water, metres, added to "
                             "relative SRT altitudes (default 0)")
    parser.add_argument("--time-offset", type=float, default=0.0, metavar="S",
                        help="laser logs: log time (s after its first row) at the clip's "
                             "first frame (default 0)")


def check_altitude_offsets(args: argparse.Namespace) -> None:
    """InputError naming the option whose value is implausible or not a number."""
    in_range(args.launch_height, LAUNCH_HEIGHT_M, "--launch-height")
    number(args.time_offset, "--time-offset")
