"""``--device``, shared by the commands that compute with torch: where the fit, the edge
network and its training run (core.device)."""

import argparse
import sys
from typing import TYPE_CHECKING

from dolphinfit.core.device import (
    AUTO, CPU, CUDA, DEFAULT_DEVICE, DEVICES, device_line, resolve_device,
)

if TYPE_CHECKING:
    import torch


def add_device_argument(parser: argparse.ArgumentParser, where: str) -> None:
    """``--device``; ``where`` says what computes there ("where the fit computes")."""
    parser.add_argument("--device", choices=DEVICES, default=DEFAULT_DEVICE,
                        help=f"{where}: {AUTO} (a CUDA GPU when torch sees one, else the "
                             f"CPU), {CPU} or {CUDA} (default {DEFAULT_DEVICE})")


def chosen_device(args: argparse.Namespace) -> "torch.device":
    """--device resolved (InputError naming it for cuda where torch sees no GPU); on a GPU,
    a line on stderr naming it."""
    device = resolve_device(args.device)
    line = device_line(device)
    if line is not None:
        print(line, file=sys.stderr)
    return device
