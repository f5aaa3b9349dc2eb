"""Train the project's own networks again from synthetic clips, reproducibly.

  dolphinfit train edges --out PATH [--clips N] [--hard-clips N] [--steps N] [--seed S]
                         [--workers N] [--device auto|cpu|cuda]

`edges` trains the edge network, which draws the animal's outline in the network tracker's
window (core/segment/edge_net.py). It renders --clips random synthetic clips and --hard-clips
of the hard scenes (surfacing, heavy glitter, faint deep passes, dark animals over sand) into
the cache (none of them the bench suite's; about 30 s each, on --workers processes; kept for
the next run), cuts the tracker's windows out of them and fits the network on patches of them for
--steps steps (about 0.6 s each on two cores), then writes the weights and a record of the run
to --out. --device is where the network trains: auto (the default) takes a CUDA GPU when the
installed torch sees one, else the CPU; the clips and windows are made on the CPU. Weights
trained on a GPU differ from the CPU's in float rounding. The bundled weights are
resources/models/edge_net_v1.npz, made with the defaults on the CPU:

  dolphinfit --threads 2 train edges --device cpu --out resources/models/edge_net_v1.npz
"""

import argparse
import json
from dataclasses import replace
from pathlib import Path

from dolphinfit.app.commands.device_option import add_device_argument, chosen_device
from dolphinfit.app.progress import terminal_progress
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.output_paths import check_output_file
from dolphinfit.core.limits import count

NETWORKS = ("edges",)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The network, the output and the recipe's sizes."""
    from dolphinfit.core.segment.edge_training import TrainSettings
    defaults = TrainSettings()
    parser.add_argument("network", choices=NETWORKS, help="which network")
    parser.add_argument("--out", type=Path, required=True, help="the weights file (.npz)")
    parser.add_argument("--clips", type=int, default=defaults.clips,
                        help=f"random synthetic clips to train on (default {defaults.clips})")
    parser.add_argument("--hard-clips", type=int, default=defaults.hard_clips,
                        help=f"clips of the hard scenes besides (default {defaults.hard_clips})")
    parser.add_argument("--steps", type=int, default=defaults.steps,
                        help=f"optimisation steps (default {defaults.steps})")
    parser.add_argument("--seed", type=int, default=defaults.seed,
                        help=f"draws the clips and the training (default {defaults.seed})")
    parser.add_argument("--workers", type=int, default=2,
                        help="processes rendering clips (default 2)")
    add_device_argument(parser, "where the network trains")


def run(args: argparse.Namespace) -> int:
    """Check the options, train, write the weights and print the held-out scores."""
    from dolphinfit.core.segment.edge_training import TrainSettings, train_edges
    if args.out.suffix != ".npz":
        raise InputError(f"--out {args.out}: the weights are written as .npz")
    check_output_file(args.out, "--out ")
    settings = replace(TrainSettings(), clips=count(args.clips, 10, "--clips"),
                       hard_clips=count(args.hard_clips, 0, "--hard-clips"),
                       steps=count(args.steps, 1, "--steps"), seed=count(args.seed, 0, "--seed"))
    workers = count(args.workers, 1, "--workers")
    record = train_edges(settings, args.out, workers, terminal_progress(),
                         device=chosen_device(args))
    print(json.dumps(record["checks"][-1]))
    print(f"wrote {args.out}")
    return 0
