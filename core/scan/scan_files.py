"""A clip's scan on disk: ``STEM_scan.json`` to read back (so that a clip is not scanned
twice) and ``STEM_scan.csv``, one row per animal and sampled frame, for people and
spreadsheets."""

import csv
from dataclasses import asdict, fields
from pathlib import Path

from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.io.json_file import read_tagged_dataclass, write_json
from dolphinfit.core.measure.morphometrix import number_text
from dolphinfit.core.scan.clip_scan import ClipScan
from dolphinfit.core.scan.frame_scores import FrameScore

SCAN_FORMAT = "dolphinfit-scan"
SCAN_VERSION = 1
SCORE_COLUMNS = [field.name for field in fields(FrameScore) if field.name != "faults"]


def write_scan_json(path: Path, scan: ClipScan) -> None:
    """Write the scan (atomically) for ``read_scan_json``."""
    write_json(path, {"format": SCAN_FORMAT, "version": SCAN_VERSION, **asdict(scan)})


def read_scan_json(path: Path) -> ClipScan:
    """A scan written by ``write_scan_json``; InputError naming the file otherwise."""
    return read_tagged_dataclass(path, ClipScan, SCAN_FORMAT, SCAN_VERSION, "scan")


def write_scan_csv(path: Path, scan: ClipScan) -> None:
    """Write (atomically) one row per animal and sampled frame: the clip, the rank among the
    animal's best frames (empty when not among them), whether it is usable and why not, and
    every score."""
    ranks = {(animal, score.frame_idx): rank for animal in scan.animal_ids()
             for rank, score in enumerate(scan.best(animal), start=1)}
    with atomic_path(Path(path)) as tmp, tmp.open("w", newline="", encoding="utf-8") as file:
        writer = csv.writer(file)
        writer.writerow(["clip", "best_rank", "usable", *SCORE_COLUMNS, "faults"])
        for score in scan.scores:
            rank = ranks.get((score.animal_id, score.frame_idx))
            values = asdict(score)
            writer.writerow([scan.clip_name, "" if rank is None else rank,
                             "yes" if score.is_usable else "no",
                             *(_cell(values[name]) for name in SCORE_COLUMNS),
                             "; ".join(score.faults)])


def _cell(value: float | int) -> str:
    """A number as CSV text: whole numbers as they are, others to 10 digits, empty for
    unknown (NaN)."""
    if isinstance(value, int):
        return str(value)
    return "" if value != value else number_text(value)
