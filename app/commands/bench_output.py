"""One way every bench prints its figures: a table, or with ``--json`` one JSON object with
the run's record (``run``: the bench, its options, the date, the machine and torch's
threads), so that a kept JSON says how it was made (the manual's benchmarks page is built
from such files)."""

import argparse
import datetime
import json
import os
import platform
from collections.abc import Callable

NOT_OPTIONS = ("run", "module", "command", "suite_name", "json")


def run_record(args: argparse.Namespace) -> dict:
    """The bench's name and the options given a value, the date, the machine and the torch
    threads used."""
    import torch

    return {"bench": args.suite_name,
            "options": {key: value for key, value in vars(args).items()
                        if key not in NOT_OPTIONS and isinstance(value, (str, int, float,
                                                                          bool))},
            "date": datetime.date.today().isoformat(),
            "machine": f"{os.cpu_count()} CPU cores, {platform.machine()}, "
                       f"{platform.system()}",
            "torch_threads": torch.get_num_threads()}


def emit(args: argparse.Namespace, figures: dict, table: Callable[[dict], str]) -> int:
    """Print ``figures`` as JSON (``--json``, with the run's record) or as ``table`` does;
    exit code 0."""
    print(json.dumps({**figures, "run": run_record(args)}, indent=2) if args.json
          else table(figures))
    return 0
