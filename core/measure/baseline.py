"""The elliptical baseline end to end: pixel measurements + calibration → values with intervals.

One function for the CLI, the GUI and the batch runner: fill unmeasured stations, scale pixels
to metres, run the elliptical chain once on the nominal inputs and, optionally, the Monte Carlo
with a per-source uncertainty budget. The result records how it was made and says what the
user should know about it (provisional HW ratios, filled stations, BCI outside the fit range).
"""

import threading
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from dolphinfit.core.measure.annotation import PixelMeasurements
from dolphinfit.core.measure.condition import MassModel
from dolphinfit.core.measure.elliptical import (
    BAI_RANGE, TAIL_EXTRAPOLATED, EllipticalResult, apply_tail, fill_skipped,
    measure_elliptical,
)
from dolphinfit.core.measure.hw_ratios import HWRatios
from dolphinfit.core.measure.stations import STATION_PCT
from dolphinfit.core.measure.uncertainty import (
    ERROR_SOURCES, ErrorModel, MonteCarloResult, monte_carlo, summary_json, uncertainty_budget,
)
from dolphinfit.core.progress import ProgressCallback, part_of

# Scalar outputs summarised in the JSON's "uncertainty" (MonteCarloResult field names)
SUMMARISED = ("length_m", "volume_m3", "volume_circular_m3", "bai", "bai_parabola", "bci",
              "mass_kg")


@dataclass(frozen=True)
class BaselineSettings:
    """The choices behind an elliptical result: HW table, tail option, mass model, BAI range."""

    hw: HWRatios
    tail: str = TAIL_EXTRAPOLATED
    mass_model: MassModel = MassModel()
    bai_range: tuple[float, float] = BAI_RANGE


@dataclass(frozen=True, eq=False)
class BaselineEstimate:
    """Nominal values, their Monte Carlo summary and each error source's share.

    ``measured``: the pixels as measured (NaN = not measured); ``is_filled``: (S,) stations the
    volume needed that were filled by interpolation; ``point``: the chain on the nominal
    inputs (0-d arrays, (S,) per station); ``interval`` and ``budget``: None / empty when no
    Monte Carlo was asked for.
    """

    measured: PixelMeasurements
    is_filled: np.ndarray
    m_per_px: float
    settings: BaselineSettings
    errors: ErrorModel
    point: EllipticalResult
    interval: MonteCarloResult | None
    budget: dict[str, MonteCarloResult]

    def warnings(self) -> list[str]:
        """What the user must know to read the numbers, one sentence each."""
        notes = []
        hw = self.settings.hw
        if hw.is_provisional:
            notes.append(f"HW ratios {hw.name!r} are provisional: {hw.description or hw.source}")
        if self.settings.tail != TAIL_EXTRAPOLATED and hw.carries_tail_ratio:
            notes.append("no HW data at 90 % and 95 %: the 85 % ratio is carried (provisional)")
        if self.is_filled.any():
            pct = ", ".join(f"{p:g} %" for p in STATION_PCT[self.is_filled])
            notes.append(f"stations not measured, filled by linear interpolation: {pct}")
        if bool(self.point.condition.is_outside_fit_range):
            low, high = self.settings.mass_model.bci_fit_range
            notes.append(f"BCI {float(self.point.condition.bci):+.3f} lies outside "
                         f"{low:+g}…{high:+g}, where the density model is not trusted")
        return notes

    def to_json(self) -> dict[str, Any]:
        """JSON-ready dict; keys carry units, top-level values are the nominal estimates."""
        p, c = self.point, self.point.condition
        ratios, _ = self.settings.hw.completed()
        stations = [{
            "station_pct": pct,
            "width_px": None if np.isnan(w_px) else float(w_px),
            "width_m": float(w_m), "height_m": float(h_m), "hw_ratio": float(ratio),
            "is_filled": bool(filled),
        } for pct, w_px, w_m, h_m, ratio, filled in zip(
            STATION_PCT.tolist(), self.measured.widths_px, p.widths_m, p.heights_m, ratios,
            self.is_filled)]
        hw = self.settings.hw
        return {
            "length_m": float(p.length_m), "volume_m3": float(p.volume_m3),
            "volume_circular_m3": float(p.volume_circular_m3), "bai": float(p.bai),
            "bai_parabola": float(p.bai_parabola), "surface_area_m2": float(p.surface_area_m2),
            "surface_area_parabola_m2": float(p.surface_area_parabola_m2),
            "expected_volume_m3": float(c.expected_volume_m3), "bci": float(c.bci),
            "density_kg_m3": float(c.density_kg_m3), "mass_kg": float(c.mass_kg),
            "is_bci_outside_fit_range": bool(c.is_outside_fit_range),
            "length_px": float(self.measured.length_px), "m_per_px": self.m_per_px,
            "is_mirrored": self.measured.is_mirrored,
            "stations": stations,
            "settings": {
                "tail": self.settings.tail,
                "hw_ratios": {"name": hw.name, "source": hw.source,
                              "is_provisional": hw.is_provisional,
                              "carries_tail_ratio": hw.carries_tail_ratio},
                "mass_model": asdict(self.settings.mass_model),
                "bai_range": list(self.settings.bai_range),
            },
            "uncertainty": None if self.interval is None else self._uncertainty_json(),
            "warnings": self.warnings(),
        }

    def _uncertainty_json(self) -> dict[str, Any]:
        mc = self.interval
        return {
            "num_draws": mc.num_draws,
            "errors": asdict(self.errors),
            **{name: summary_json(getattr(mc, name)) for name in SUMMARISED},
            "widths_m": summary_json(mc.widths_m),
            "fraction_outside_fit_range": mc.fraction_outside_fit_range,
            "budget_sd": {source: {name: float(getattr(result, name).sd) for name in SUMMARISED}
                          for source, result in self.budget.items()},
        }


def estimate_baseline(pixels: PixelMeasurements, focal_px: float, altitude_m: float,
                      settings: BaselineSettings, errors: ErrorModel, num_draws: int,
                      rng: np.random.Generator, progress: ProgressCallback | None = None,
                      cancel: threading.Event | None = None) -> BaselineEstimate:
    """Elliptical volume, BAI, BCI and mass, with intervals when ``num_draws`` > 0.

    pixels: length and (S,) widths in pixels; focal_px: focal length in pixels; altitude_m:
    camera height above the water. Metres per pixel = altitude_m / focal_px (DESIGN §3).
    progress: draws done of all the Monte Carlo's, the budget's included (core.progress).
    """
    tail, hw = settings.tail, settings.hw
    filled_px, is_filled = fill_skipped(pixels.widths_px, tail)
    nominal = PixelMeasurements(pixels.length_px, apply_tail(filled_px, tail), pixels.is_mirrored)
    m_per_px = altitude_m / focal_px
    ratios, _ = hw.completed()
    point = measure_elliptical(nominal.length_px * m_per_px, nominal.widths_px * m_per_px,
                               ratios, tail, settings.mass_model, settings.bai_range)
    interval, budget = None, {}
    if num_draws > 0:
        args = (nominal, focal_px, altitude_m, hw, tail, errors, num_draws, rng,
                settings.mass_model, settings.bai_range)
        total = (1 + len(ERROR_SOURCES)) * num_draws
        interval = monte_carlo(*args, part_of(progress, 0, total), cancel)
        budget = uncertainty_budget(*args, part_of(progress, num_draws, total), cancel)
    return BaselineEstimate(measured=pixels, is_filled=is_filled, m_per_px=m_per_px,
                            settings=settings, errors=errors, point=point, interval=interval,
                            budget=budget)
