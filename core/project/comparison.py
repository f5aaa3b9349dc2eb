"""Both methods side by side for one animal: the elliptical baseline of a measured frame and
the model-based 3D fit, with the difference in % of the elliptical value, and the row per
animal that the comparison CSV holds (joinable with CollatriX tables on ``Image``).

The fit carries no interval of its own yet: its bounds are None.
"""

from dataclasses import dataclass

from core.fit.result import FitResult
from core.measure.baseline import BaselineEstimate
from core.measure.uncertainty import Summary

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


@dataclass(frozen=True)
class MethodValue:
    """One method's value of a quantity, with its 95 % interval when it has one."""

    value: float
    low: float | None = None
    high: float | None = None


@dataclass(frozen=True)
class ComparisonRow:
    """A quantity by both methods; ``difference_pct`` = (fit − elliptical) / elliptical × 100."""

    key: str
    label: str
    unit: str
    elliptical: MethodValue
    fitted: MethodValue

    @property
    def difference_pct(self) -> float:
        return 100.0 * (self.fitted.value / self.elliptical.value - 1.0)


def _elliptical_value(estimate: BaselineEstimate, key: str) -> float:
    point = estimate.point
    return float(getattr(point, key) if key in ("length_m", "volume_m3")
                 else getattr(point.condition, key))


def compare(estimate: BaselineEstimate, fit: FitResult) -> list[ComparisonRow]:
    """Length, volume, BCI, density and mass of an elliptical estimate and a fit."""
    rows = []
    for key, label, unit in QUANTITIES:
        summary = interval_of(estimate, key)
        elliptical = MethodValue(_elliptical_value(estimate, key),
                                 None if summary is None else float(summary.low),
                                 None if summary is None else float(summary.high))
        rows.append(ComparisonRow(key, label, unit, elliptical,
                                  MethodValue(float(getattr(fit, key)))))
    return rows


def comparison_csv_row(image: str, animal_id: str, fit_status: str,
                       rows: list[ComparisonRow]) -> dict[str, object]:
    """One CSV row per animal: ``Image`` (the measured frame's image ID, CollatriX's join
    key), the animal, then per quantity the elliptical value and interval, the fit's value
    and the difference in %."""
    row: dict[str, object] = {"Image": image, "animal_id": animal_id, "fit_status": fit_status}
    for r in rows:
        row.update({f"{r.key}_ell": r.elliptical.value, f"{r.key}_ell_lo95": r.elliptical.low,
                    f"{r.key}_ell_hi95": r.elliptical.high, f"{r.key}_fit": r.fitted.value,
                    f"{r.key}_diff_pct": r.difference_pct})
    return row
