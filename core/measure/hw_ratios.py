"""Height/width (HW) ratios per station: presets with provenance, user CSVs, or the 3D model.

The elliptical baseline takes each station's height as width × HW ratio (DESIGN.md §7). HW
dominates its uncertainty for dolphins (about ±25 % on volume, reference/morphometrics.md §4),
so every table carries its source, whether it is provisional, and a one-SD uncertainty per
station that the Monte Carlo samples.

CSV format (``resources/hw_ratios/*.csv`` and user files): ``# key: value`` header lines
(``name``, ``description``, ``source``, ``provisional: yes|no``), then the columns
``station_pct,hw_ratio[,hw_ratio_sd]``. An empty ``hw_ratio`` means no data; only the 90 % and
95 % stations may lack data, and then carry the 85 % ratio (a provisional choice that the
result labels; morphometrics.md §2.2).
"""

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.atomic import atomic_path
from dolphinfit.core.io.text_input import cell_number, read_text
from dolphinfit.core.measure.elliptical import TAIL_IDX, TAIL_SOURCE_IDX
from dolphinfit.core.measure.stations import STATION_PCT
from dolphinfit.core.resources import RESOURCES_DIR

PRESETS_DIR = RESOURCES_DIR / "hw_ratios"
DEFAULT_PRESET = "tursiops-provisional"
FROM_MODEL = "model"  # the --hw value that takes the ratios from the 3D model
REQUIRED_COLUMNS = ("station_pct", "hw_ratio")
SD_COLUMN = "hw_ratio_sd"
HEADER_KEYS = ("name", "description", "source", "provisional")
YES_NO = {"yes": True, "no": False}


@dataclass(frozen=True, eq=False)
class HWRatios:
    """An HW table: ``ratios`` (S,) height / width, NaN where there are no data (90 % and
    95 % only); ``sd`` (S,) one-SD uncertainty of each ratio (0 = none stated)."""

    name: str
    ratios: np.ndarray
    sd: np.ndarray
    source: str
    is_provisional: bool
    description: str = ""

    @property
    def carries_tail_ratio(self) -> bool:
        """Whether the 90 % / 95 % ratios are missing and taken from the 85 % station."""
        return bool(np.isnan(self.ratios[list(TAIL_IDX)]).any())

    def completed(self) -> tuple[np.ndarray, np.ndarray]:
        """(S,) ratios and (S,) SDs with missing 90 % / 95 % values carried from 85 %."""
        ratios, sd = self.ratios.copy(), self.sd.copy()
        for idx in TAIL_IDX:
            if np.isnan(ratios[idx]):
                ratios[idx], sd[idx] = ratios[TAIL_SOURCE_IDX], sd[TAIL_SOURCE_IDX]
        return ratios, sd


def _parse_header(lines: list[str], path: Path) -> dict[str, str]:
    """``# key: value`` lines → dict; InputError naming the line for unknown keys."""
    header = {}
    for line_no, line in enumerate(lines, start=1):
        key, sep, value = line.lstrip("#").partition(":")
        key = key.strip().lower()
        if not sep or key not in HEADER_KEYS:
            raise InputError(f"{path}, line {line_no}: expected '# key: value' with a key "
                             f"among {', '.join(HEADER_KEYS)}")
        header[key] = value.strip()
    return header


def read_hw_csv(path: Path) -> HWRatios:
    """Read an HW table (format in the module docstring); InputError when it is malformed."""
    path = Path(path)
    lines = read_text(path).splitlines()
    num_header = next((i for i, line in enumerate(lines) if not line.startswith("#")), len(lines))
    header = _parse_header(lines[:num_header], path)
    rows = list(csv.DictReader(io.StringIO("\n".join(lines[num_header:]))))
    columns = rows[0].keys() if rows else ()
    if any(column not in columns for column in REQUIRED_COLUMNS):
        raise InputError(f"{path}, line {num_header + 1}: expected the columns "
                         f"{','.join(REQUIRED_COLUMNS)}[,{SD_COLUMN}]")
    ratios, sd = np.full(len(STATION_PCT), np.nan), np.zeros(len(STATION_PCT))
    seen = set()
    for line_no, row in enumerate(rows, start=num_header + 2):
        pct = cell_number(path, line_no, "station_pct", row["station_pct"])
        matches = np.flatnonzero(np.isclose(STATION_PCT, pct))
        if len(matches) != 1 or pct in seen:
            raise InputError(f"{path}, line {line_no}: station_pct {row['station_pct']!r} is "
                             f"not one of 5, 10, … 95, or repeats an earlier row")
        seen.add(pct)
        ratio = cell_number(path, line_no, "hw_ratio", row["hw_ratio"])
        spread = cell_number(path, line_no, SD_COLUMN, row.get(SD_COLUMN) or "0")
        if ratio <= 0 or not spread >= 0:
            raise InputError(f"{path}, line {line_no}: hw_ratio must be positive and "
                             f"{SD_COLUMN} non-negative")
        ratios[matches[0]], sd[matches[0]] = ratio, spread
    missing = [f"{p:g} %" for i, p in enumerate(STATION_PCT)
               if np.isnan(ratios[i]) and i not in TAIL_IDX]
    if missing:
        raise InputError(f"{path}: no HW ratio for the stations {', '.join(missing)} "
                         f"(only 90 % and 95 % may be left empty)")
    provisional = header.get("provisional", "no").lower()
    if provisional not in YES_NO:
        raise InputError(f"{path}: header 'provisional' must be yes or no, got {provisional!r}")
    return HWRatios(name=header.get("name", path.stem), ratios=ratios, sd=sd,
                    source=header.get("source", str(path)), is_provisional=YES_NO[provisional],
                    description=header.get("description", ""))


def write_hw_csv(path: Path, hw: HWRatios) -> None:
    """Write an HW table in the format ``read_hw_csv`` reads (atomically); stations without
    data (90 % and 95 % only) are left empty."""
    lines = [f"# name: {hw.name}", f"# description: {hw.description}", f"# source: {hw.source}",
             f"# provisional: {'yes' if hw.is_provisional else 'no'}",
             ",".join((*REQUIRED_COLUMNS, SD_COLUMN))]
    lines += [f"{pct:g},{'' if np.isnan(ratio) else repr(float(ratio))},{float(sd)!r}"
              for pct, ratio, sd in zip(STATION_PCT, hw.ratios, hw.sd)]
    with atomic_path(Path(path)) as tmp:
        tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")


def preset_names() -> list[str]:
    """Names of the bundled HW presets."""
    return sorted(path.stem for path in PRESETS_DIR.glob("*.csv"))


def load_hw_preset(name: str = DEFAULT_PRESET) -> HWRatios:
    """A bundled preset by name; InputError listing the available ones otherwise."""
    path = PRESETS_DIR / f"{name}.csv"
    if not path.exists():
        raise InputError(f"unknown HW ratio preset {name!r}; available: "
                         f"{', '.join(preset_names())}, {FROM_MODEL}, or a CSV file")
    return read_hw_csv(path)
