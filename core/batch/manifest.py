"""A batch manifest: a CSV with one row per clip and animal.

Columns (header names; only ``clip`` is required; paths are relative to the manifest's folder):

- ``clip``: the video. ``animal``: the animal's ID (default "1"); a clip and animal pair
  appears once.
- ``altitude``: metres above the water, or an altitude CSV, DJI SRT or laser log (empty: the
  clip's SRT beside it). ``launch_height_m`` (added to relative SRT altitudes),
  ``time_offset_s`` (laser logs), ``altitude_source``: laser, barometer or manual (default
  barometer for an SRT, laser for a laser log, else manual), which sets the elliptical
  method's altitude error.
  ``altitude_calibration``: a `dolphinfit calibrate altitude` file of the clip's camera: the
  altitudes are corrected by it and both methods' intervals take its spread as their error.
- ``camera``: a preset name, or ``sensor_width_mm`` and ``focal_mm``. ``lens``: a `dolphinfit
  calibrate lens` file of its video mode (default: the one kept with the camera preset, if
  any): the fit sees its frames and masks undistorted, the elliptical method takes its mask's
  midline and widths through it.
- ``masks``: a mask PNG folder, mask video or .npz; or ``seed`` for the built-in tracker:
  ``auto``, a click ``X,Y`` or a box ``X,Y,W,H`` in pixels of frame ``seed_frame`` (default
  0). Neither: ``auto``.
- ``scan``: the clip's scan (`dolphinfit scan`: its STEM_scan.json, or the folder it was
  written to); ``animal`` is then the scan's animal number, the tracker is seeded on the
  animal in its best frame (no ``seed`` with it), and the elliptical method measures the
  animal's ``best`` best usable frames (default: as many as the scan listed), the summary
  giving the one of median volume.
- ``start_s``, ``end_s``, ``fps``, ``quality`` (quick, standard, thorough), ``refraction``,
  ``roi`` (yes/no): the app's fit settings (core/project/fit_settings.py); ``config``: a
  FitConfig JSON they apply to.

Every cell is checked here: a bad one is an InputError naming the manifest, the row (the
file's line, the header being row 1) and the column.
"""

import csv
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

from dolphinfit.core.batch.task import BatchTask, FitInputs, MaskMeasurement
from dolphinfit.core.camera_presets import get_preset
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.pipeline import CameraChoice
from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.io.telemetry import altitude_file_kind, find_srt_sidecar
from dolphinfit.core.io.text_input import read_text
from dolphinfit.core.limits import (
    ALTITUDE_M, FOCAL_MM, FPS, LAUNCH_HEIGHT_M, SENSOR_WIDTH_MM, Limits, count, in_range,
    number, time_window,
)
from dolphinfit.core.measure.altitude_calibration import read_altitude_calibration
from dolphinfit.core.measure.lens import LensModel, read_lens
from dolphinfit.core.measure.preset_lens import preset_lens
from dolphinfit.core.measure.annotation import ALTITUDE_SOURCES
from dolphinfit.core.measure.uncertainty import DEFAULT_NUM_DRAWS
from dolphinfit.core.project.fit_settings import (
    QUALITY_STEP_SCALE, FitSettings, fit_config, fit_dir,
)
from dolphinfit.core.scan.fit_seed import seed_at
from dolphinfit.core.scan.frame_scores import FrameScore
from dolphinfit.core.scan.scan_files import read_scan_json
from dolphinfit.core.segment.segmenter import AutoSeed, BoxSeed, PointSeed, Seed

COLUMNS = ("clip", "animal", "altitude", "launch_height_m", "time_offset_s", "altitude_source",
           "altitude_calibration", "lens",
           "camera", "sensor_width_mm", "focal_mm", "masks", "seed", "seed_frame", "scan", "best",
           "start_s", "end_s", "fps", "quality", "refraction", "roi", "config")
REQUIRED = ("clip",)
DEFAULT_ANIMAL = "1"
BOOLEANS = {"yes": True, "true": True, "1": True, "no": False, "false": False, "0": False}
SRT_SOURCE = "barometer"  # DJI SRT altitudes come from the barometer
T = TypeVar("T")


@dataclass(frozen=True)
class Row:
    """One manifest row: its cells and where it is, for messages."""

    manifest: Path
    row: int
    cells: dict[str, str]

    def where(self, column: str) -> str:
        return f"{self.manifest}: row {self.row}, column {column!r}"

    def text(self, column: str) -> str:
        return (self.cells.get(column) or "").strip()

    def parsed(self, column: str, parse: Callable[[str], T], default: T) -> T:
        """The cell through ``parse`` (ValueError or InputError → InputError naming the cell);
        ``default`` when empty."""
        text = self.text(column)
        if not text:
            return default
        try:
            return parse(text)
        except (ValueError, InputError) as exc:
            raise InputError(f"{self.where(column)}: {text!r}: {exc}") from None

    def number(self, column: str, limits: Limits | None = None,
               default: float | None = None) -> float | None:
        """The cell as a finite number (inside ``limits`` when given); ``default`` if empty."""
        text, where = self.text(column), self.where(column)
        if not text:
            return default
        try:
            value = float(text)
        except ValueError:
            raise InputError(f"{where}: expected a number, got {text!r}") from None
        return number(value, where) if limits is None else in_range(value, limits, where)

    def path(self, column: str) -> Path | None:
        """The cell as an existing path relative to the manifest's folder."""
        text = self.text(column)
        if not text:
            return None
        path = (self.manifest.parent / text).resolve()
        if not path.exists():
            raise InputError(f"{self.where(column)}: {path} does not exist")
        return path


def _seed(text: str, frame_idx: int) -> Seed:
    if text.lower() == "auto":
        return AutoSeed(frame_idx)
    values = [float(v) for v in text.split(",")]
    if len(values) == 2:
        return PointSeed(values[0], values[1], frame_idx)
    if len(values) == 4 and values[2] > 0 and values[3] > 0:
        return BoxSeed(*(round(v) for v in values), frame_idx)
    raise ValueError("expected auto, a click X,Y or a box X,Y,W,H (pixels)")


def _boolean(text: str) -> bool:
    if text.lower() not in BOOLEANS:
        raise ValueError("expected yes or no")
    return BOOLEANS[text.lower()]


def _altitude(row: Row, clip: Path) -> float | Path | None:
    text = row.text("altitude")
    if not text:
        if find_srt_sidecar(clip) is None:
            raise InputError(f"{row.where('altitude')}: empty, and no {clip.stem}.SRT beside "
                             f"the clip")
        return None
    try:
        return in_range(float(text), ALTITUDE_M, row.where("altitude"))
    except ValueError:
        pass
    if not (row.manifest.parent / text).exists():
        raise InputError(f"{row.where('altitude')}: {text!r} is neither metres nor an existing "
                         f"file")
    return row.path("altitude")


def _preset_lens(row: Row, preset: str | None) -> LensModel | None:
    """The lens kept with the row's camera preset, if any (core/measure/preset_lens.py)."""
    try:
        return preset_lens(preset)
    except InputError as exc:
        raise InputError(f"{row.where('camera')}: {exc}") from None


def _read_cell_file(row: Row, column: str, read: Callable[[Path], T]) -> T | None:
    """The file the cell names, read here so that a bad one stops the batch before any work
    (None when the cell is empty)."""
    path = row.path(column)
    if path is None:
        return None
    try:
        return read(path)
    except InputError as exc:
        raise InputError(f"{row.where(column)}: {exc}") from None


def _camera(row: Row) -> CameraChoice:
    preset = row.text("camera") or None
    sensor = row.number("sensor_width_mm", SENSOR_WIDTH_MM)
    focal = row.number("focal_mm", FOCAL_MM)
    if preset is not None:
        if sensor is not None or focal is not None:
            raise InputError(f"{row.where('camera')}: give a preset or sensor_width_mm and "
                             f"focal_mm, not both")
        row.parsed("camera", get_preset, None)
    elif (sensor is None) != (focal is None):
        missing = "focal_mm" if focal is None else "sensor_width_mm"
        raise InputError(f"{row.where(missing)}: empty; give both sensor_width_mm and focal_mm")
    return CameraChoice(preset, sensor, focal)


def _base_config(row: Row) -> FitConfig:
    path = row.path("config")
    if path is None:
        return FitConfig()
    try:
        return FitConfig.from_json(read_json(path, "the fit config"))
    except InputError as exc:
        raise InputError(f"{row.where('config')}: {exc}") from None


def _fit_config(row: Row) -> FitConfig:
    base = _base_config(row)
    start = row.number("start_s", default=base.start_s)
    end = row.number("end_s", default=base.end_s)
    time_window(start, end, row.where("start_s"), row.where("end_s"))
    quality = row.text("quality") or "standard"
    if quality not in QUALITY_STEP_SCALE:
        raise InputError(f"{row.where('quality')}: {quality!r}, expected one of "
                         f"{', '.join(QUALITY_STEP_SCALE)}")
    settings = FitSettings(start_s=start, end_s=end, fps=row.number("fps", FPS, base.fps),
                           quality=quality,
                           refraction=row.parsed("refraction", _boolean, base.use_refraction),
                           roi=row.parsed("roi", _boolean, base.use_roi))
    return fit_config(settings, base)


def _altitude_source(row: Row, altitude: float | Path | None) -> str:
    """The row's altitude source, by default that of its altitude: a DJI SRT's barometer,
    a laser log's laser, else "manual"."""
    kind = "srt" if altitude is None else (
        altitude_file_kind(altitude) if isinstance(altitude, Path) else None)
    default = {"srt": SRT_SOURCE, "laser": "laser", "astro": "laser"}.get(kind, "manual")
    source = row.text("altitude_source") or default
    if source not in ALTITUDE_SOURCES:
        raise InputError(f"{row.where('altitude_source')}: {source!r}, expected one of "
                         f"{', '.join(ALTITUDE_SOURCES)}")
    return source


def _scan_picks(row: Row, clip: Path, animal: str) -> list[FrameScore]:
    """The best usable frames of ``animal`` in the row's scan, best first (none without a
    scan); InputError naming the cell when the scan is not the clip's or the animal has none."""
    path = row.path("scan")
    if path is None:
        if row.text("best"):
            raise InputError(f"{row.where('best')}: needs a scan (column 'scan')")
        return []
    if row.text("seed"):
        raise InputError(f"{row.where('seed')}: give a scan or a tracker seed, not both")
    if path.is_dir():
        path = path / f"{clip.stem}_scan.json"
    try:
        scan = read_scan_json(path)
    except InputError as exc:
        raise InputError(f"{row.where('scan')}: {exc}") from None
    if scan.clip_name != clip.name:
        raise InputError(f"{row.where('scan')}: {path.name} is the scan of {scan.clip_name}, "
                         f"not of {clip.name}")
    numbers = {str(number): number for number in scan.animal_ids()}
    if animal not in numbers:
        raise InputError(f"{row.where('animal')}: {animal!r} is not an animal of the scan "
                         f"(its animals: {', '.join(numbers) or 'none'})")
    picks = scan.best(numbers[animal], row.parsed("best", _whole(1), scan.settings.best_count))
    if not picks:
        raise InputError(f"{row.where('animal')}: the scan found no usable frame of animal "
                         f"{animal}")
    return picks


def task_from_row(row: Row, num_draws: int = DEFAULT_NUM_DRAWS) -> BatchTask:
    """The batch task of one manifest row."""
    clip = row.path("clip")
    if clip is None:
        raise InputError(f"{row.where('clip')}: empty; name the clip's video")
    animal = row.text("animal") or DEFAULT_ANIMAL
    altitude = _altitude(row, clip)
    masks = row.path("masks")
    if masks is not None and row.text("seed"):
        raise InputError(f"{row.where('seed')}: give masks or a tracker seed, not both")
    seed_frame = row.parsed("seed_frame", _whole(0), 0)
    picks = _scan_picks(row, clip, animal)
    seed = (seed_at(picks[0]) if picks
            else row.parsed("seed", lambda text: _seed(text, seed_frame), AutoSeed(seed_frame)))
    frames = tuple(sorted(pick.frame_idx for pick in picks))
    camera = _camera(row)
    lens = _read_cell_file(row, "lens", read_lens) or _preset_lens(row, camera.preset)
    fit = FitInputs(clip=clip, altitude=altitude,
                    launch_height_m=row.number("launch_height_m", LAUNCH_HEIGHT_M, 0.0),
                    time_offset_s=row.number("time_offset_s", default=0.0),
                    camera=camera, masks=masks, seed=seed, config=_fit_config(row),
                    altitude_calibration=_read_cell_file(row, "altitude_calibration",
                                                         read_altitude_calibration),
                    also_frames=frames, lens=lens)
    return BatchTask(name=fit_dir(row.manifest, row.text("clip"), animal).name,
                     clip=row.text("clip"), animal_id=animal,
                     where=f"{row.manifest}: row {row.row}", fit=fit,
                     measurement=MaskMeasurement(_altitude_source(row, altitude),
                                                 num_draws=num_draws, frames=frames,
                                                 lens=lens))


def _whole(minimum: int) -> Callable[[str], int]:
    """A cell's parser: a whole number ≥ ``minimum``."""
    return lambda text: count(int(text), minimum, "a whole number")


def read_manifest(path: Path, num_draws: int = DEFAULT_NUM_DRAWS) -> list[BatchTask]:
    """Every row's task; InputError naming the manifest, row and column of the first bad
    cell."""
    path = Path(path)
    lines = read_text(path).splitlines()
    reader = csv.DictReader(lines)
    header = [name.strip() for name in (reader.fieldnames or [])]
    reader.fieldnames = header
    unknown = [name for name in header if name not in COLUMNS]
    if unknown:
        raise InputError(f"{path}: row 1, column {unknown[0]!r}: unknown column; the columns "
                         f"are {', '.join(COLUMNS)}")
    for name in REQUIRED:
        if name not in header:
            raise InputError(f"{path}: row 1, column {name!r}: missing")
    tasks: list[BatchTask] = []
    seen: dict[tuple[str, str], int] = {}
    for cells in reader:
        row = Row(path, reader.line_num, cells)
        if None in cells:
            raise InputError(f"{path}: row {row.row}: more cells than the header's "
                             f"{len(header)} columns")
        task = task_from_row(row, num_draws)
        key = (str(task.fit.clip), task.animal_id)
        if key in seen:
            raise InputError(f"{row.where('animal')}: {task.animal_id!r} of {task.clip} is "
                             f"already in row {seen[key]}")
        seen[key] = row.row
        tasks.append(task)
    if not tasks:
        raise InputError(f"{path}: no rows; one row per clip and animal")
    return tasks
