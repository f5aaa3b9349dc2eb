"""One task on a Dask worker: skip it when its folder records the same inputs, else fit and
measure the animal into a hidden folder beside it, record how it ended, and put the folder in
place (``core.io.atomic.atomic_folder``: a kill at any moment leaves the old complete folder,
or none, and a leftover that the task's next run removes).

A failure of one method is recorded with the other's figures and does not stop the batch.
"""

import time
from dataclasses import replace
from pathlib import Path
from typing import Any

from dolphinfit.core.batch.inputs import inputs_digest, task_inputs
from dolphinfit.core.batch.mask_baseline import NOTE, mask_baseline
from dolphinfit.core.batch.record import (
    STATUS_COMPLETE, STATUS_FAILED, TaskRecord, read_record, write_record,
)
from dolphinfit.core.batch.summary import elliptical_values, fit_interval_values, fit_values
from dolphinfit.core.batch.task import BatchTask, ProjectMeasurement
from dolphinfit.core.device import CPU, resolve_device
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.outputs import write_outputs
from dolphinfit.core.fit.pipeline import FitRun, run_fit
from dolphinfit.core.io.atomic import atomic_folder
from dolphinfit.core.measure.baseline import BaselineEstimate
from dolphinfit.core.measure.records import write_exports
from dolphinfit.core.model.template import load_template
from dolphinfit.core.project.evaluate import all_keys, frame_results

ELLIPTICAL_STEM = "elliptical"  # STEM_measure.json, STEM_mmx.csv, STEM_wide.csv


def describe(exc: Exception) -> str:
    """An error in words: bad input as its message, anything else with its type."""
    return str(exc) if isinstance(exc, InputError) else f"{type(exc).__name__}: {exc}"


def run_task(task: BatchTask, out_dir: Path, retry_failed: bool = False,
             device: str = CPU) -> TaskRecord:
    """Run ``task`` into ``out_dir/task.name`` unless a finished record of the same inputs is
    there (a failed one runs again only with ``retry_failed``); its record. The fit computes
    on ``device`` (a core.device name, resolved here, on the worker); the record does not
    say where."""
    out_dir = Path(out_dir)
    folder = out_dir / task.name
    start = time.perf_counter()
    try:
        inputs = task_inputs(task)
    except (InputError, OSError) as exc:  # an input vanished since the batch was planned
        return TaskRecord(task.name, task.clip, task.animal_id, STATUS_FAILED, describe(exc))
    digest = inputs_digest(inputs)
    done = read_record(folder)
    if (done is not None and done.inputs_digest == digest
            and (done.status == STATUS_COMPLETE or not retry_failed)):
        return replace(done, reused=True)
    with atomic_folder(folder) as partial:
        values, errors, notes = _run_methods(task, partial, device)
        values["notes"] = "; ".join(notes)
        record = TaskRecord(task.name, task.clip, task.animal_id,
                            STATUS_FAILED if errors else STATUS_COMPLETE, "; ".join(errors),
                            digest, inputs, values, time.perf_counter() - start)
        write_record(partial, record)
    return record


def _run_methods(task: BatchTask, folder: Path,
                 device: str) -> tuple[dict[str, Any], list[str], list[str]]:
    """Both methods' values, the errors and the notes."""
    values: dict[str, Any] = {}
    errors: list[str] = []
    notes: list[str] = []
    run = None
    if task.fit is None:
        notes.append("no 3D fit: only video clips are fitted")
    else:
        try:
            run = _fit(task, folder, device)
            values.update(fit_values(run.result))
            if not run.result.finished:
                errors.append(f"fit {run.result.status}: {run.result.status_message}")
        except Exception as exc:  # noqa: BLE001 (recorded; the batch goes on)
            errors.append(f"fit: {describe(exc)}")
    estimate = None
    try:
        if isinstance(task.measurement, ProjectMeasurement):
            elliptical, estimate = _project_elliptical(task.measurement, folder, notes)
            values.update(elliptical)
        elif run is None:
            errors.append("elliptical: it measures the fit's masks, and there is no fit")
        else:
            elliptical, estimate, picked = mask_baseline(run, task.fit.camera,
                                                         task.measurement,
                                                         folder / ELLIPTICAL_STEM,
                                                         task.fit.altitude_calibration)
            values.update(elliptical)
            notes += [f"elliptical {NOTE}", *picked]
    except Exception as exc:  # noqa: BLE001 (recorded; the batch goes on)
        errors.append(f"elliptical: {describe(exc)}")
    if run is not None and estimate is not None:
        values.update(fit_interval_values(estimate, run.result, run.clip.width_px))
    return values, errors, notes


def _fit(task: BatchTask, folder: Path, device: str) -> FitRun:
    fit = task.fit
    run = run_fit(fit.clip, fit.altitude, fit.masks, fit.camera, fit.config,
                  fit.launch_height_m, seed=fit.seed, time_offset_s=fit.time_offset_s,
                  altitude_calibration=fit.altitude_calibration, also_frames=fit.also_frames,
                  lens=fit.lens, device=resolve_device(device))
    write_outputs(run.result, run.data, load_template(), folder)
    return run


def _project_elliptical(m: ProjectMeasurement, folder: Path, notes: list[str]
                        ) -> tuple[dict[str, Any], BaselineEstimate | None]:
    """Measure every frame the user measured on the animal (exports of each in the folder);
    the summary takes the first, as the app's comparison does, with its estimate."""
    keys = all_keys(m.project, m.clip_idx, m.animal_idx)
    if not keys:
        notes.append("elliptical: no frame measured in the project")
        return {}, None
    results, skipped = frame_results(m.project, m.project_path, keys, m.num_draws)
    if not results:
        raise InputError("; ".join(skipped))
    for result in results:
        write_exports(folder / f"{ELLIPTICAL_STEM}_{result.image_id}", result.source,
                      result.estimate, result.record)
    notes += skipped
    if len(results) > 1:
        notes.append(f"elliptical of the first of {len(results)} measured frames")
    first = results[0]
    frame_idx = m.project.clips[m.clip_idx].animals[m.animal_idx].measurements[
        first.key.measurement].frame_idx
    return (elliptical_values(first.estimate, first.record, first.image_id, frame_idx),
            first.estimate)
