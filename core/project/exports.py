"""Exports of any set of measured frames (one frame, one animal, a whole project).

Files, all written atomically, under ``out_dir``:

- ``STEM_results.json``: schema version; per frame (keyed by its export name, the image ID)
  the clip, animal and frame with the result JSON; per animal the mean, SD and range of
  SUMMARY_KEYS over its exported frames.
- ``STEM_wide.csv``: our wide table (core.measure.collatrix: metres, pixels, Xcertainty's
  calibration, results), one row per frame, with the columns ``clip``, ``animal_id`` and
  ``frame_idx`` in front.
- ``STEM_collatrix.csv``: the table CollatriX's body-condition tool reads as it is, one row
  per frame, ``Image_ID`` being NAME.
- ``STEM_xcertainty.csv``: the frames as Xcertainty reads them (core.project.xcertainty), and
  ``STEM_xcertainty_calibration.csv`` the shots of the project's altitude calibrations, if any.
- ``STEM_mmx/NAME.csv``: one MorphoMetriX v2 long CSV per frame.
- ``STEM_annotations/NAME.json``: the frame as `dolphinfit measure` reads it
  (core.measure.annotation_json): clicks as clicked, camera, recorded altitude. Where the clip
  has them, ``STEM_lenses/NAME.json`` is its lens model and ``STEM_altitude_calibrations/
  NAME.json`` its altitude calibration, for ``--lens`` and ``--altitude-calibration``; with
  those and the project's ``--hw`` and ``--tail``, `dolphinfit measure` gives the frame's
  length and volume as here.
- ``STEM_receipts/NAME.png``: the receipt of each frame whose image ``frames`` gives.

NAME is the frame's image ID; where several animals share a frame, the animal ID is appended.
"""

import math
import os
import re
import threading
from collections import Counter
from collections.abc import Callable, Sequence
from contextlib import suppress
from dataclasses import asdict
from pathlib import Path
from types import TracebackType
from typing import Self

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.collatrix import write_wide_csv
from dolphinfit.core.io.frame_source import FrameSource
from dolphinfit.core.io.json_file import write_json
from dolphinfit.core.io.media import open_media
from dolphinfit.core.measure.altitude_calibration import write_altitude_calibration
from dolphinfit.core.measure.annotation_json import write_annotation_json
from dolphinfit.core.measure.lens import write_lens
from dolphinfit.core.measure.morphometrix import write_morphometrix_v2
from dolphinfit.core.measure.receipt import draw_receipt, write_png
from dolphinfit.core.measure.records import collatrix_csv_row, wide_csv_row
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel
from dolphinfit.core.project.model import Project, get_measurement
from dolphinfit.core.project.project_file import media_path
from dolphinfit.core.project.calibrations import clip_calibration
from dolphinfit.core.project.results import FrameResult, Spread, animal_summary, frame_annotation
from dolphinfit.core.project.xcertainty import calibration_rows, measurement_row

EXPORTS_SCHEMA_VERSION = 1
UNSAFE_NAME_CHARS = re.compile(r"[^A-Za-z0-9._-]+")

FrameImages = Callable[[FrameResult], np.ndarray | None]


def export_names(project: Project, results: Sequence[FrameResult]) -> list[str]:
    """File-safe export name of each result: its image ID, plus the animal ID where two
    results share an image ID (several animals on one frame)."""
    counts = Counter(r.image_id for r in results)
    names = []
    for r in results:
        name = r.image_id
        if counts[name] > 1:
            name += "_" + project.clips[r.key.clip].animals[r.key.animal].animal_id
        names.append(UNSAFE_NAME_CHARS.sub("-", name))
    if len(set(names)) < len(names):
        raise InputError("two exported frames have the same image and animal: "
                         "check the animal IDs")
    return names


def _spread_json(spread: Spread) -> dict[str, float | int | None]:
    """A spread with NaN (the SD of one frame) as null, which JSON can hold."""
    return {key: None if isinstance(value, float) and math.isnan(value) else value
            for key, value in asdict(spread).items()}


def _identity(project: Project, result: FrameResult) -> dict[str, object]:
    """Clip (media path), animal ID and frame index of a result."""
    clip = project.clips[result.key.clip]
    return {"clip": clip.media_path, "animal_id": clip.animals[result.key.animal].animal_id,
            "frame_idx": get_measurement(project, result.key).frame_idx}


def results_json(project: Project, results: Sequence[FrameResult],
                 names: Sequence[str]) -> dict:
    """The content of STEM_results.json (module docstring)."""
    by_animal: dict[tuple[int, int], list[tuple[str, FrameResult]]] = {}
    for name, result in zip(names, results):
        by_animal.setdefault((result.key.clip, result.key.animal), []).append((name, result))
    animals = []
    for members in by_animal.values():
        frames = [r for _, r in members]
        identity = _identity(project, frames[0])
        animals.append({"clip": identity["clip"], "animal_id": identity["animal_id"],
                        "frames": [name for name, _ in members],
                        "summary": {key: _spread_json(s)
                                    for key, s in animal_summary(frames).items()}})
    return {"schema_version": EXPORTS_SCHEMA_VERSION,
            "frames": {name: {**_identity(project, r), "result": r.record}
                       for name, r in zip(names, results)},
            "animals": animals}


def _media_from(folder: Path, project_dir: Path | None, clip_media_path: str) -> str | None:
    """The clip's media relative to ``folder`` (absolute on another drive); None without
    ``project_dir``, which the clip's path is relative to."""
    if project_dir is None:
        return None
    media = Path(project_dir) / clip_media_path
    try:
        return Path(os.path.relpath(media, folder)).as_posix()
    except ValueError:  # Windows: another drive
        return media.as_posix()


def write_frame_inputs(project: Project, result: FrameResult, name: str, out_dir: Path,
                       stem: str, project_dir: Path | None = None) -> list[Path]:
    """The annotation file of one result and, where its clip has them, its lens model and
    altitude calibration (module docstring); the paths written. ``project_dir``: the project
    file's folder, to give the media's path relative to the annotation."""
    source = result.source
    recorded_m = (source.record.altitude_m if source.recorded_altitude_m is None
                  else source.recorded_altitude_m)
    folder = out_dir / f"{stem}_annotations"
    media = _media_from(folder, project_dir, project.clips[result.key.clip].media_path)
    annotation = folder / f"{name}.json"
    write_annotation_json(annotation, frame_annotation(project, result.key, recorded_m,
                                                       source.altitude_source, media))
    written = [annotation]
    lens = project.clips[result.key.clip].lens
    if lens is not None:
        written.append(out_dir / f"{stem}_lenses" / f"{name}.json")
        write_lens(lens, written[-1])
    calibration = clip_calibration(project, result.key.clip)
    if calibration is not None:
        written.append(out_dir / f"{stem}_altitude_calibrations" / f"{name}.json")
        write_altitude_calibration(calibration, written[-1])
    return written


def export_frames(project: Project, results: Sequence[FrameResult], out_dir: Path, stem: str,
                  frames: FrameImages | None = None, progress: ProgressCallback | None = None,
                  cancel: threading.Event | None = None,
                  project_dir: Path | None = None) -> list[Path]:
    """Write the exports of ``results`` (frames of ``project``); the paths written.

    frames: the RGB frame (H, W, 3) uint8 of a result, or None, for its receipt; project_dir:
    the project file's folder, for the media paths of the annotations (None: as stored in the
    project, relative to it); progress:
    called with (frames done, frames in all) after each frame's files; cancel: checked between
    frames (core.progress). On any exception, a cancel included, the files written so far are
    removed again.
    """
    if not results:
        raise InputError("nothing to export: no measured frame with a length and a width")
    out_dir = Path(out_dir)
    names = export_names(project, results)
    written: list[Path] = []
    try:
        rows, collatrix_rows, xcertainty_rows = [], [], []
        for done, (name, result) in enumerate(zip(names, results), start=1):
            check_cancel(cancel)
            mmx = out_dir / f"{stem}_mmx" / f"{name}.csv"
            write_morphometrix_v2(mmx, result.source.record)
            written.append(mmx)
            written += write_frame_inputs(project, result, name, out_dir, stem, project_dir)
            rows.append({**_identity(project, result),
                         **wide_csv_row(result.source, result.estimate, result.record,
                                        csv_name=mmx.name)})
            collatrix_rows.append(collatrix_csv_row(result.source, result.estimate,
                                                    csv_name=mmx.name, image_id=name))
            xcertainty_rows.append(measurement_row(project, result))
            rgb = frames(result) if frames is not None else None
            if rgb is not None:
                annotation = get_measurement(project, result.key).to_annotation()
                receipt = out_dir / f"{stem}_receipts" / f"{name}.png"
                write_png(receipt, draw_receipt(rgb, annotation, result.record))
                written.append(receipt)
            if progress is not None:
                progress(Progress("write", done, len(results), name))
        check_cancel(cancel)
        tables = {out_dir / f"{stem}_wide.csv": rows,
                  out_dir / f"{stem}_collatrix.csv": collatrix_rows,
                  out_dir / f"{stem}_xcertainty.csv": xcertainty_rows}
        if project.calibrations:
            tables[out_dir / f"{stem}_xcertainty_calibration.csv"] = calibration_rows(project)
        summary = out_dir / f"{stem}_results.json"
        write_json(summary, results_json(project, results, names))
        written.append(summary)
        for path, table in tables.items():
            write_wide_csv(path, table)
            written.append(path)
    except BaseException:
        _remove(written)
        raise
    return [summary, *tables, *written[:-1 - len(tables)]]


def _remove(paths: Sequence[Path]) -> None:
    """Delete files, then their folders where that left them empty."""
    for path in paths:
        path.unlink(missing_ok=True)
    for folder in {path.parent for path in paths}:
        with suppress(OSError):  # not empty: it held other files before
            folder.rmdir()


class MediaFrames:
    """The frame of each result from its clip's media, each media opened once: the ``frames``
    argument of :func:`export_frames`. A clip whose media or frame cannot be read gets no
    receipt; ``notes`` says why. Close it (or use it as a context manager) when done."""

    def __init__(self, project: Project, project_path: Path) -> None:
        self._project = project
        self._project_path = Path(project_path)
        self._sources: dict[int, FrameSource | None] = {}
        self.notes: list[str] = []

    def __call__(self, result: FrameResult) -> np.ndarray | None:
        clip = self._project.clips[result.key.clip]
        frame_idx = get_measurement(self._project, result.key).frame_idx
        try:
            if result.key.clip not in self._sources:
                self._sources[result.key.clip] = None  # stays None if opening fails
                self._sources[result.key.clip] = open_media(media_path(self._project_path,
                                                                       clip))
            source = self._sources[result.key.clip]
            return None if source is None else source.frame(frame_idx)
        except (InputError, OSError, IndexError) as exc:
            self.notes.append(f"{clip.name} frame {frame_idx}: no receipt ({exc})")
            return None

    def close(self) -> None:
        for source in self._sources.values():
            if source is not None:
                source.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 traceback: TracebackType | None) -> None:
        self.close()
