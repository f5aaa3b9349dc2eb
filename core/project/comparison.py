"""Both methods side by side for one animal: the elliptical baseline of a measured frame and
the model-based 3D fit, with their difference (in % of the elliptical value; for BCI, in BCI
units), and the row per animal that the comparison CSV holds (joinable with CollatriX tables
on ``Image``).

The fit's interval comes from core.measure.fit_uncertainty, drawn on the elliptical estimate's
error model, HW table, mass model and scale, with as many draws: both methods' intervals rest
on the same assumptions. Without a Monte Carlo neither has one.
"""

import threading
from dataclasses import dataclass
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.result import FitResult
from dolphinfit.core.fit.result_io import read_fit_result
from dolphinfit.core.project.fit_inputs import changed_since_fit
from dolphinfit.core.measure.collatrix import write_wide_csv
from dolphinfit.core.measure.baseline import BaselineEstimate
from dolphinfit.core.measure.fit_uncertainty import FitInterval, outline_sd_px
from dolphinfit.core.measure.uncertainty import Summary
from dolphinfit.core.progress import ProgressCallback, check_cancel
from dolphinfit.core.project.evaluate import frame_results
from dolphinfit.core.project.model import MeasurementKey, Project

QUANTITIES = (  # result key, label, unit
    ("length_m", "Length", "m"), ("volume_m3", "Volume", "m³"), ("bci", "BCI", ""),
    ("density_kg_m3", "Density", "kg/m³"), ("mass_kg", "Mass", "kg"),
)


def interval_of(estimate: BaselineEstimate, key: str) -> Summary | None:
    """The Monte Carlo summary of one QUANTITIES key; None without a Monte Carlo.

    Density is not drawn: it falls linearly with BCI, so its mean, SD and percentiles are the
    BCI's mapped through the mass model's line (the bounds swap, the slope being negative).
    """
    mc = estimate.interval
    if mc is None:
        return None
    if key != "density_kg_m3":
        return getattr(mc, key)
    model, bci = estimate.settings.mass_model, mc.bci
    intercept, slope = model.density_intercept_kg_m3, model.density_slope_kg_m3
    return Summary(mean=intercept - slope * bci.mean, sd=slope * bci.sd,
                   low=intercept - slope * bci.high, high=intercept - slope * bci.low)


def fit_interval_of(estimate: BaselineEstimate, fit: FitResult,
                    frame_width_px: int) -> FitInterval | None:
    """The fit's Monte Carlo beside the estimate's (module doc), its outline SD that of a frame
    ``frame_width_px`` wide and the fit's edge blur; None when the estimate has none or the fit has no positive
    volume and length. Loads torch: worker only."""
    from dolphinfit.core.fit.interval import result_interval

    if estimate.interval is None or not (fit.volume_m3 > 0 and fit.length_m > 0):
        return None
    return result_interval(fit, estimate.m_per_px, estimate.errors, estimate.settings.hw,
                           outline_sd_px(frame_width_px, fit.edge_blur_px),
                           estimate.settings.mass_model,
                           estimate.interval.num_draws)


@dataclass(frozen=True)
class MethodValue:
    """One method's value of a quantity, with its 95 % interval when it has one."""

    value: float
    low: float | None = None
    high: float | None = None

    def text(self, fmt: str) -> str:
        """The value in ``fmt``, with its interval in brackets when it has one."""
        value = format(self.value, fmt)
        if self.low is None or self.high is None:
            return value
        return f"{value} ({format(self.low, fmt)}–{format(self.high, fmt)})"


def method_value(value: float, summary: Summary | None) -> MethodValue:
    """A value with the 95 % interval of ``summary`` (None: without one)."""
    if summary is None:
        return MethodValue(value)
    return MethodValue(value, float(summary.low), float(summary.high))


@dataclass(frozen=True)
class ComparisonRow:
    """A quantity by both methods and their difference: (fit − elliptical) / elliptical in
    %, except for BCI, itself a relative difference near 0, where it is fit − elliptical."""

    key: str
    label: str
    unit: str
    elliptical: MethodValue
    fitted: MethodValue

    @property
    def is_relative(self) -> bool:
        """Whether ``difference`` is in % of the elliptical value."""
        return self.key != "bci"

    @property
    def difference(self) -> float:
        change = self.fitted.value - self.elliptical.value
        return 100.0 * change / self.elliptical.value if self.is_relative else change


def _elliptical_value(estimate: BaselineEstimate, key: str) -> float:
    point = estimate.point
    return float(getattr(point, key) if key in ("length_m", "volume_m3")
                 else getattr(point.condition, key))


def compare(estimate: BaselineEstimate, fit: FitResult,
            frame_width_px: int) -> list[ComparisonRow]:
    """Length, volume, BCI, density and mass of an elliptical estimate and a fit, each with
    its 95 % interval when the estimate has a Monte Carlo (``frame_width_px``: the clip's)."""
    fitted = fit_interval_of(estimate, fit, frame_width_px)
    return [ComparisonRow(key, label, unit,
                          method_value(_elliptical_value(estimate, key),
                                       interval_of(estimate, key)),
                          method_value(float(getattr(fit, key)),
                                       None if fitted is None else getattr(fitted, key)))
            for key, label, unit in QUANTITIES]


def comparison_csv_row(image: str, animal_id: str, fit_status: str,
                       rows: list[ComparisonRow],
                       changed: list[str] | None = None) -> dict[str, object]:
    """One CSV row per animal: ``Image_ID`` (the measured frame's image ID, as in the
    CollatriX table's ``Image_ID``, the join key), the animal, the fit's status and the
    clip's inputs ``changed`` since the fit (core.project.fit_inputs), then per quantity the
    elliptical value and interval, the fit's value and interval and the difference
    (``_diff_pct`` in %, ``bci_diff`` in BCI units)."""
    row: dict[str, object] = {"Image_ID": image, "animal_id": animal_id, "fit_status": fit_status,
                              "fit_out_of_date_because": "; ".join(changed or [])}
    for r in rows:
        row.update({f"{r.key}_ell": r.elliptical.value, f"{r.key}_ell_lo95": r.elliptical.low,
                    f"{r.key}_ell_hi95": r.elliptical.high, f"{r.key}_fit": r.fitted.value,
                    f"{r.key}_fit_lo95": r.fitted.low, f"{r.key}_fit_hi95": r.fitted.high,
                    f"{r.key}_diff{'_pct' if r.is_relative else ''}": r.difference})
    return row


def project_comparison_rows(project: Project, project_path: Path, num_draws: int,
                            progress: ProgressCallback | None = None,
                            cancel: threading.Event | None = None) -> tuple[list[dict], list[str]]:
    """One comparison row per animal that has a saved fit and a measured frame (its first),
    and, for the animals left out, why."""
    keys, fits, notes = [], [], []
    for c, clip in enumerate(project.clips):
        for a, animal in enumerate(clip.animals):
            where = f"{clip.name} {animal.animal_id}"
            if animal.fit_path is None or not animal.measurements:
                why = "no 3D fit" if animal.fit_path is None else "not measured"
                notes.append(f"{where}: {why}")
                continue
            keys.append(MeasurementKey(c, a, 0))
            fits.append(project_path.parent / animal.fit_path)
    results, skipped = frame_results(project, project_path, keys, num_draws, progress, cancel)
    by_key = {r.key: r for r in results}
    rows = []
    for key, folder in zip(keys, fits):
        if key not in by_key:
            continue
        check_cancel(cancel)
        animal = project.clips[key.clip].animals[key.animal]
        try:
            fit = read_fit_result(folder)
        except (InputError, OSError) as exc:
            notes.append(f"{project.clips[key.clip].name} {animal.animal_id}: {exc}")
            continue
        clip = project.clips[key.clip]
        rows.append(comparison_csv_row(by_key[key].image_id, animal.animal_id, fit.status,
                                       compare(by_key[key].estimate, fit,
                                               clip.known_camera().image_width_px),
                                       changed_since_fit(project, clip, animal)))
    return rows, notes + skipped


def write_comparison_csv(path: Path, rows: list[dict]) -> None:
    """The comparison CSV (atomic); InputError when there is nothing to write."""
    if not rows:
        raise InputError("nothing to compare: no animal has both a measured frame and a 3D fit")
    write_wide_csv(path, rows)
