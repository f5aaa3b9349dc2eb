"""The manual's generated pages, written by mkdocs-gen-files at each build: the command line
from its argparse definitions, the keyboard shortcuts from the app's action table, every fit
setting from FitConfig's source, the benchmarks from the bench runs' JSON in docs/bench/, and
the three splits' table in the accuracy page (docs/split_summary.py). Nothing here is copied
by hand, so none of it can fall out of date."""

import ast
import inspect
import json
import os
import sys
from collections.abc import Iterator
from dataclasses import MISSING, fields
from pathlib import Path

import mkdocs_gen_files

sys.path.insert(0, str(Path(__file__).parent))   # the table of the splits lies beside this
import split_summary  # noqa: E402

os.environ["COLUMNS"] = "96"   # argparse wraps its help to this width

from dolphinfit.app.cli import build_parser  # noqa: E402 (argparse reads COLUMNS)
from dolphinfit.core.fit.config import FitConfig, LearningRates, LossWeights  # noqa: E402
from dolphinfit.ui.action_table import CTRL, MOUSE_GESTURES, load_action_table  # noqa: E402

BENCH_DIR = Path(__file__).parent / "bench"
PAPERS = "the paper's value"


def subparsers_of(parser):
    """(name, parser) of each subcommand of ``parser``, in order; none for a leaf."""
    for action in parser._actions:   # argparse keeps no public list of its subparsers
        if action.__class__.__name__ == "_SubParsersAction":
            yield from action.choices.items()


def cli_sections(parser, prefix: str) -> Iterator[str]:
    """A heading and the help text of each command under ``parser``, depth first."""
    for name, sub in subparsers_of(parser):
        command = f"{prefix} {name}"
        yield f"## `{command}`\n\n```text\n{sub.format_help().rstrip()}\n```\n"
        yield from cli_sections(sub, command)


def cli_page() -> str:
    parser = build_parser()
    return ("# Command line\n\nEvery command's `--help`, generated from its argparse "
            "definitions when the manual is built. Exit codes: 0 success, 1 internal error, "
            "2 bad input (the message names the file or option), 130 stopped with Ctrl-C.\n\n"
            f"```text\n{parser.format_help().rstrip()}\n```\n\n"
            + "\n".join(cli_sections(parser, "dolphinfit")))


def shortcuts_page() -> str:
    menus, actions = load_action_table()
    rows = [f"| {a.where} | {a.shortcut.replace('+', ' + ') if a.shortcut else ''} | {a.label} |"
            for a in sorted(actions, key=lambda a: menus.index(a.menu))]
    mouse = [f"| {gesture.replace(CTRL, 'Ctrl+')} | {what} |" for gesture, what in MOUSE_GESTURES]
    return ("# Keyboard shortcuts\n\nEvery menu action of the app and its key, generated from "
            "the table the menus are built from (`resources/ui/actions.json`); Help → Keyboard "
            "shortcuts (F1) shows the same table. On macOS Ctrl is ⌘.\n\n"
            "| menu | key | action |\n|---|---|---|\n" + "\n".join(rows)
            + "\n\n## Mouse, on the frame\n\n| gesture | what it does |\n|---|---|\n"
            + "\n".join(mouse) + "\n\nIn the Frames dock, Enter measures the selected frame "
            "and Delete puts it aside.\n")


def field_comments(cls, missing: str) -> dict[str, str]:
    """Each dataclass field's comment in the source: the lines of comment just above it and
    the one at the end of its line; ``missing`` for a field with neither."""
    source = inspect.getsource(cls)
    lines = source.splitlines()
    comments = {}
    for node in ast.parse(source).body[0].body:
        if not isinstance(node, ast.AnnAssign):
            continue
        row = node.lineno - 1
        above = []
        k = row - 1
        while k >= 0 and lines[k].strip().startswith("#"):
            above.insert(0, lines[k].strip().lstrip("#").strip())
            k -= 1
        inline = lines[row].split("#", 1)[1].strip() if "#" in lines[row] else ""
        comments[node.target.id] = " ".join(above + ([inline] if inline else [])) or missing
    return comments


def default_text(field) -> str:
    if field.default is not MISSING:
        return f"`{field.default!r}`"
    return "see below" if field.default_factory is not MISSING else ""


def config_table(cls, prefix: str = "", missing: str = "") -> str:
    comments = field_comments(cls, missing)
    rows = [f"| `{prefix}{f.name}` | {default_text(f)} | "
            f"{comments.get(f.name, '').replace('|', '/')} |" for f in fields(cls)]
    return "| setting | default | what it does and why |\n|---|---|---|\n" + "\n".join(rows)


def fit_config_page() -> str:
    return ("# Fit settings\n\nEvery field of `FitConfig` (`core/fit/config.py`), generated "
            "from its source when the manual is built. A fit configuration is JSON with "
            "these keys (`dolphinfit fit --config FILE`, the batch manifest's `config` "
            "column); every result records the configuration it was made with. Defaults are "
            "the paper's where it gives them; the others say why.\n\n"
            f"## The fit\n\n{config_table(FitConfig)}\n\n"
            f"## Loss weights (`weights`)\n\n"
            f"{config_table(LossWeights, 'weights.', PAPERS)}\n\n"
            f"## Learning rates (`learning_rates`)\n\n"
            f"{config_table(LearningRates, 'learning_rates.', PAPERS)}\n")


LONGEST_LIST = 20   # a longer list is shown by its length only


SHARES = ("_error", "_share", "_floor")   # keys whose values are fractions: shown in %


def cell(value, key: str = "") -> str:
    """One value as table text: fractions (by their key) in %, other numbers to 6
    significant digits, short lists in full."""
    if isinstance(value, float):
        return f"{100 * value:+.2f} %" if key.endswith(SHARES) else f"{value:.6g}"
    if isinstance(value, list):
        if len(value) > LONGEST_LIST:
            return f"({len(value)} items)"
        return " · ".join("/".join(cell(v, key) for v in item) if isinstance(item, list)
                          else cell(item, key) for item in value)
    if isinstance(value, dict):
        return f"`{json.dumps(value)[:60]}`"
    return str(value).replace("|", "/")


def is_records(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(r, dict) for r in value)


def flat(record: dict) -> dict:
    """A record with each group of plain numbers in it spread into columns ``key.name``
    (e.g. a run's seconds by stage); other groups left out."""
    columns = {}
    for key, value in record.items():
        if not isinstance(value, dict):
            columns[key] = value
        elif all(isinstance(v, (int, float)) for v in value.values()):
            columns.update({f"{key}.{name}": v for name, v in value.items()})
    return columns


def records_table(records: list[dict]) -> str:
    """A list of records as one Markdown table (``flat``)."""
    rows = [flat(r) for r in records]
    keys = list(dict.fromkeys(k for r in rows for k in r))
    return ("| " + " | ".join(keys) + " |\n|" + "---|" * len(keys) + "\n"
            + "\n".join("| " + " | ".join(cell(r.get(k, ""), k.split(".")[0]) for k in keys)
                        + " |" for r in rows))


def bench_tables(data: dict, depth: int = 3) -> Iterator[str]:
    """A bench run's JSON as tables: each group of plain figures (numbers, text, short lists
    of them) as one two-column table, each list of records as a table under its key's
    heading, each nested group under its own heading."""
    plain = {k: v for k, v in data.items() if not isinstance(v, dict) and not is_records(v)}
    if plain:
        yield "| figure | value |\n|---|---|\n" + "\n".join(
            f"| {k} | {cell(v, k)} |" for k, v in plain.items()) + "\n"
    for key, value in data.items():
        if is_records(value):
            yield f"{'#' * depth} {key}\n\n{records_table(value)}\n"
        elif isinstance(value, dict):
            yield f"{'#' * depth} {key}\n"
            yield from bench_tables(value, min(depth + 1, 6))


TITLES = {"real": "Against people: real drone images measured by hand",
          "fit": "The fit on synthetic clips with known truth",
          "masks": "Masks on synthetic clips with known truth",
          "scan": "The scan's picks", "render": "The renderer's speed",
          "e2e": "From the clip to the result", "app": "The app's speed",
          "batch": "Batches"}


def command_line(run: dict) -> str:
    """The bench command that wrote a run's JSON, from its record (``threads`` is the
    command's own option, before the bench's)."""
    options = dict(run["options"])
    threads = options.pop("threads", None)
    words = ["dolphinfit", *([f"--threads {threads}"] if threads else []), "bench", run["bench"]]
    words += [f"--{key.replace('_', '-')}" + ("" if value is True else f" {value}")
              for key, value in options.items() if value is not False]
    return " ".join([*words, "--json"])


def benchmarks_page() -> str:
    parts = ["# Benchmarks\n\nGenerated when the manual is built from the JSON of the bench "
             "runs kept in `docs/bench/`, each with the command that wrote it. These are the "
             "current figures; how they were reached is in the "
             "[decision records](decisions/index.md), what they mean in "
             "[What the accuracy figures mean](explanation/accuracy.md).\n"]
    runs = [json.loads(path.read_text()) for path in sorted(BENCH_DIR.glob("*.json"))]
    order = list(TITLES)   # people first, then the synthetic splits, then speed
    for figures in sorted(runs, key=lambda r: order.index(r["run"]["bench"])
                          if r["run"]["bench"] in order else len(order)):
        run = figures.pop("run")
        parts.append(f"## {TITLES.get(run['bench'], run['bench'])}\n\n`{command_line(run)}`"
                     f" on {run['date']}, {run['machine']}, {run['torch_threads']} torch "
                     f"thread{'s' if run['torch_threads'] != 1 else ''}.\n")
        parts.extend(bench_tables(figures))
    return "\n".join(parts)


PAGES = {"reference/cli.md": cli_page, "reference/shortcuts.md": shortcuts_page,
         "reference/fit-config.md": fit_config_page, "benchmarks.md": benchmarks_page}

for page, make in PAGES.items():
    with mkdocs_gen_files.open(page, "w") as out:
        out.write(make())

ACCURACY = "explanation/accuracy.md"
with mkdocs_gen_files.open(ACCURACY, "r") as page:
    written = split_summary.with_table(page.read())
with mkdocs_gen_files.open(ACCURACY, "w") as page:
    page.write(written)
