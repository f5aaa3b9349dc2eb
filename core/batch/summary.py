"""The batch's summary table: one row per clip and animal with both methods' length, volume,
BCI, density and mass, each with its 95 % Monte Carlo interval (the fit's drawn on the elliptical
estimate's error model: core.project.comparison), the task's status and error."""

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from dolphinfit.core.batch.record import TaskRecord
from dolphinfit.core.fit.result import FitResult
from dolphinfit.core.measure.collatrix import write_wide_csv
from dolphinfit.core.measure.baseline import BaselineEstimate
from dolphinfit.core.project.comparison import QUANTITIES, fit_interval_of, interval_of

SUMMARY_CSV = "summary.csv"
COLUMNS = ("clip", "animal_id", "status", "error", "notes", "folder", "reused", "Image_ID",
           "ell_frame",
           *(f"{key}_{suffix}" for key, _, _ in QUANTITIES
             for suffix in ("ell", "ell_lo95", "ell_hi95", "fit", "fit_lo95", "fit_hi95")),
           "fit_status", "fit_unreliable_because", "fit_frames", "fit_mean_iou", "fit_warnings",
           "seconds")


def elliptical_values(estimate: BaselineEstimate, record: dict, image_id: str,
                      frame_idx: int) -> dict[str, Any]:
    """The elliptical columns of one measured frame (``record``: its result JSON)."""
    values: dict[str, Any] = {"Image_ID": image_id, "ell_frame": frame_idx}
    for key, _, _ in QUANTITIES:
        summary = interval_of(estimate, key)
        values[f"{key}_ell"] = float(record[key])
        if summary is not None:
            values[f"{key}_ell_lo95"] = float(summary.low)
            values[f"{key}_ell_hi95"] = float(summary.high)
    return values


def fit_values(result: FitResult) -> dict[str, Any]:
    """The fit's columns."""
    values: dict[str, Any] = {f"{key}_fit": float(getattr(result, key)) for key, _, _ in QUANTITIES}
    values.update(fit_status=result.status, fit_unreliable_because=" | ".join(result.reasons),
                  fit_frames=len(result.frame_idx),
                  fit_mean_iou=float(result.iou.mean()),
                  fit_warnings=" | ".join(result.warnings))
    return values


def fit_interval_values(estimate: BaselineEstimate, result: FitResult,
                        frame_width_px: int) -> dict[str, Any]:
    """The fit's interval columns (``frame_width_px``: the clip's); none when the estimate
    has no Monte Carlo."""
    fitted = fit_interval_of(estimate, result, frame_width_px)
    if fitted is None:
        return {}
    return {f"{key}_fit_{end}95": float(getattr(getattr(fitted, key), bound))
            for key, _, _ in QUANTITIES for end, bound in (("lo", "low"), ("hi", "high"))}


def summary_row(record: TaskRecord) -> dict[str, Any]:
    """One row of the table, every column present ("" where a method has no value)."""
    values = dict(record.values)
    if "Image" in values:   # a task finished before the column was named Image_ID
        values.setdefault("Image_ID", values.pop("Image"))
    row = {**values, "clip": record.clip, "animal_id": record.animal_id,
           "status": record.status, "error": record.error, "folder": record.name,
           "reused": "yes" if record.reused else "no", "seconds": round(record.seconds, 1)}
    return {column: row.get(column, "") for column in COLUMNS}


def write_summary(path: Path, records: Sequence[TaskRecord]) -> None:
    """Write the summary CSV (atomically)."""
    write_wide_csv(path, [summary_row(r) for r in records])
