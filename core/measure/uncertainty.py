"""Monte Carlo uncertainty of the elliptical baseline: length, widths, volume, BCI and mass.

Each of D draws perturbs the inputs and reruns the whole metric chain (pixels → metres →
elliptical volume → body condition → mass); results are summarised as mean, SD and the central
95 % interval (2.5th and 97.5th percentiles), as Xcertainty reports them (reference/
ecosystem.md §9). Draws come from a numpy Generator the caller seeds.

Error sources (DESIGN.md §7):

- **Altitude**: relative error, one SD per source (``ALTITUDE_SD_FRACTION``).
- **Camera**: relative error of the focal length in pixels (focal length and the sensor width
  the video mode reads); the principal point does not enter nadir lengths.
- **Digitisation**: every click is off by an isotropic Gaussian of ``digitisation_sd_px`` per
  image axis. To first order this moves the length by the tangential errors of the rostrum and
  notch clicks; moves each station along the body by (1 − p)·ε_rostrum + p·ε_notch, which
  changes its width by the local taper; and adds the two edge clicks' errors across the body
  (a mirrored width doubles one click's error). Interior midline clicks only bend the spline:
  a second-order effect, left out. Acting on pixel lengths and widths, the same model serves
  annotations and imported MorphoMetriX measurements.
- **HW ratios**: each station's ratio moves by z·SD with one z ~ N(0, 1) per draw shared by all
  stations: HW error is a shape-level bias (e.g. captive animals standing in for wild ones,
  the paper's caveat), not independent noise per station, which would average out.

Every draw's random numbers are taken first, then the chain runs in fixed batches of
``BATCH_DRAWS`` with progress and cancel (core.progress) between them: a seed gives the same
result with or without a progress callback or cancel event.
"""

import threading
from dataclasses import dataclass, fields, is_dataclass, replace
from typing import Any, Self

import numpy as np

from dolphinfit.core.measure.annotation import PixelMeasurements
from dolphinfit.core.measure.condition import MassModel
from dolphinfit.core.measure.elliptical import BAI_RANGE, EllipticalResult, measure_elliptical
from dolphinfit.core.measure.hw_ratios import HWRatios
from dolphinfit.core.measure.stations import STATION_FRACTIONS
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel, part_of

# Altitude error, relative SD by source. Provisional defaults; calibrate per drone and flight
# where possible (Bierlich et al. 2021a, Xcertainty).
ALTITUDE_SD_FRACTION = {
    # LiDAR (LightWare SF11/C): Dawson et al. 2017 report about 1 % error on a floating target.
    "laser": 0.01,
    # DJI barometric height plus launch height: a DJI Mini study found a proportional error of
    # about 4.5 % (reference/ecosystem.md §7); drift over a flight comes on top.
    "barometer": 0.05,
    # Typed or read off a display, no measurement behind it: twice the barometer's (ours).
    "manual": 0.10,
}
# One click, per image axis. Provisional: digitisation dominates measurement variance (97 %,
# Burnett et al. 2018); 2 px is about a hundredth of a dolphin's maximum width on 4K frames.
DIGITISATION_SD_PX = 2.0
# Focal length in pixels: a verified camera preset or explicit calibrated values (0.5 %) or a
# preset marked approximate, whose video-mode sensor crop is unverified (2 %). Provisional.
FOCAL_SD_FRACTION = 0.005
FOCAL_SD_FRACTION_APPROXIMATE = 0.02
INTERVAL_PERCENTILES = (2.5, 97.5)  # central 95 % interval
DEFAULT_NUM_DRAWS = 2000
SOURCE_FIELDS = {  # error source → the ErrorModel field that sets it
    "altitude": "altitude_sd_fraction", "camera": "focal_sd_fraction",
    "digitisation": "digitisation_sd_px", "hw_ratios": "hw_sd_scale",
}
ERROR_SOURCES = tuple(SOURCE_FIELDS)
BATCH_DRAWS = 4000  # about 20 ms of work: a cancel takes effect at once
MONTE_CARLO_STAGE = "monte carlo"


@dataclass(frozen=True)
class ErrorModel:
    """SDs of the error sources (module docstring). ``hw_sd_scale`` multiplies the HW table's
    own SDs (1 = as stated, 0 = ratios taken as exact)."""

    altitude_sd_fraction: float
    focal_sd_fraction: float
    digitisation_sd_px: float
    hw_sd_scale: float = 1.0

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not (np.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be a non-negative number, got {value!r}")

    @classmethod
    def default(cls, altitude_source: str, is_camera_approximate: bool) -> Self:
        """The documented defaults for an altitude source and camera."""
        return cls(
            altitude_sd_fraction=ALTITUDE_SD_FRACTION[altitude_source],
            focal_sd_fraction=(FOCAL_SD_FRACTION_APPROXIMATE if is_camera_approximate
                               else FOCAL_SD_FRACTION),
            digitisation_sd_px=DIGITISATION_SD_PX,
        )

    def only(self, source: str) -> Self:
        """This model with every source but ``source`` (one of ERROR_SOURCES) switched off."""
        kept = SOURCE_FIELDS[source]
        return replace(self, **{name: 0.0 for name in SOURCE_FIELDS.values() if name != kept})


@dataclass(frozen=True, eq=False)
class Summary:
    """Mean, SD and central 95 % interval [low, high] of draws; each (...) per quantity."""

    mean: np.ndarray
    sd: np.ndarray
    low: np.ndarray
    high: np.ndarray


def summarize(samples: np.ndarray) -> Summary:
    """Summary over the leading (draw) axis of ``samples`` (D, ...)."""
    low, high = np.percentile(samples, INTERVAL_PERCENTILES, axis=0)
    return Summary(mean=samples.mean(axis=0), sd=samples.std(axis=0, ddof=1), low=low,
                   high=high)


def summary_json(summary: Summary) -> dict[str, Any]:
    """Mean, SD and interval as numbers (scalars) or lists (per station)."""
    return {key: np.asarray(getattr(summary, key)).tolist()
            for key in ("mean", "sd", "low", "high")}


@dataclass(frozen=True, eq=False)
class MonteCarloResult:
    """Summaries of D draws. widths_m: (S,) per station (as the volume used them)."""

    num_draws: int
    length_m: Summary
    widths_m: Summary
    volume_m3: Summary
    volume_circular_m3: Summary
    bai: Summary
    bai_parabola: Summary
    bci: Summary
    mass_kg: Summary
    fraction_outside_fit_range: float  # share of draws whose BCI lies outside the fit range


def station_taper(widths_px: np.ndarray) -> np.ndarray:
    """(S,) dw/dx at each station: central differences of the widths (S,), zero at both ends."""
    positions = np.concatenate([[0.0], STATION_FRACTIONS, [1.0]])
    padded = np.concatenate([[0.0], widths_px, [0.0]])
    return (padded[2:] - padded[:-2]) / (positions[2:] - positions[:-2])  # per unit of BL


def draw_pixels(pixels: PixelMeasurements, sd_px: float, num_draws: int,
                rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """(D,) lengths and (D, S) widths in pixels under digitisation error (module docstring).

    ``pixels.widths_px`` must be finite (filled) wherever the draws are used.
    """
    tangential = rng.normal(0.0, sd_px, size=(num_draws, 2))     # rostrum, notch
    across = rng.normal(0.0, sd_px, size=(num_draws, len(STATION_FRACTIONS), 2))  # sides A, B
    lengths = pixels.length_px + tangential[:, 1] - tangential[:, 0]
    shift_bl = ((1 - STATION_FRACTIONS) * tangential[:, :1] + STATION_FRACTIONS
                * tangential[:, 1:]) / pixels.length_px        # (D, S) in units of BL
    edge_error = 2 * across[..., 0] if pixels.is_mirrored else across[..., 0] - across[..., 1]
    widths = pixels.widths_px + station_taper(pixels.widths_px) * shift_bl + edge_error
    return lengths, widths


def draw_m_per_px(focal_px: float, altitude_m: float, errors: ErrorModel, num_draws: int,
                  rng: np.random.Generator) -> np.ndarray:
    """(D,) metres per pixel under the altitude's error, then the focal length's."""
    altitude = altitude_m * (1 + rng.normal(0.0, errors.altitude_sd_fraction, num_draws))
    focal = focal_px * (1 + rng.normal(0.0, errors.focal_sd_fraction, num_draws))
    return altitude / focal


def length_summary(length_px: float, focal_px: float, altitude_m: float, errors: ErrorModel,
                   num_draws: int, rng: np.random.Generator) -> Summary:
    """The length alone, in metres, under the errors of its two end points, the altitude and
    the camera: for a frame whose widths are not placed yet."""
    ends = rng.normal(0.0, errors.digitisation_sd_px, size=(num_draws, 2))   # rostrum, notch
    return summarize((length_px + ends[:, 1] - ends[:, 0])
                     * draw_m_per_px(focal_px, altitude_m, errors, num_draws, rng))


def draw_results(pixels: PixelMeasurements, focal_px: float, altitude_m: float, hw: HWRatios,
                 tail: str, errors: ErrorModel, num_draws: int, rng: np.random.Generator,
                 mass_model: MassModel = MassModel(),
                 bai_range: tuple[float, float] = BAI_RANGE,
                 progress: ProgressCallback | None = None,
                 cancel: threading.Event | None = None) -> EllipticalResult:
    """The elliptical chain over D perturbed inputs: an EllipticalResult with (D, ...) fields.

    pixels: filled widths (``fill_skipped``); focal_px, altitude_m: nominal calibration.
    """
    lengths_px, widths_px = draw_pixels(pixels, errors.digitisation_sd_px, num_draws, rng)
    m_per_px = draw_m_per_px(focal_px, altitude_m, errors, num_draws, rng)
    ratios, ratio_sd = hw.completed()
    shape_z = rng.normal(0.0, 1.0, size=(num_draws, 1))
    draws_hw = ratios + shape_z * errors.hw_sd_scale * ratio_sd
    lengths_m, widths_m = lengths_px * m_per_px, widths_px * m_per_px[:, None]
    batches = []
    for start in range(0, num_draws, BATCH_DRAWS):
        check_cancel(cancel)
        batch = slice(start, start + BATCH_DRAWS)
        batches.append(measure_elliptical(lengths_m[batch], widths_m[batch], draws_hw[batch],
                                          tail, mass_model, bai_range))
        if progress is not None:
            progress(Progress(MONTE_CARLO_STAGE, min(num_draws, start + BATCH_DRAWS), num_draws))
    return _concatenate(batches)


def _concatenate(batches: list[Any]) -> Any:
    """Batches of a result dataclass (nested ones included) joined along the draw axis."""
    first = batches[0]
    return type(first)(**{
        field.name: (_concatenate if is_dataclass(getattr(first, field.name))
                     else np.concatenate)([getattr(b, field.name) for b in batches])
        for field in fields(first)})


def monte_carlo(pixels: PixelMeasurements, focal_px: float, altitude_m: float, hw: HWRatios,
                tail: str, errors: ErrorModel, num_draws: int, rng: np.random.Generator,
                mass_model: MassModel = MassModel(),
                bai_range: tuple[float, float] = BAI_RANGE,
                progress: ProgressCallback | None = None,
                cancel: threading.Event | None = None) -> MonteCarloResult:
    """Mean, SD and 95 % interval of every output over ``num_draws`` ≥ 2 draws (progress:
    draws done of ``num_draws``)."""
    if num_draws < 2:
        raise ValueError(f"num_draws must be at least 2, got {num_draws}")
    draws = draw_results(pixels, focal_px, altitude_m, hw, tail, errors, num_draws, rng,
                         mass_model, bai_range, progress, cancel)
    return MonteCarloResult(
        num_draws=num_draws,
        length_m=summarize(draws.length_m),
        widths_m=summarize(draws.widths_m),
        volume_m3=summarize(draws.volume_m3),
        volume_circular_m3=summarize(draws.volume_circular_m3),
        bai=summarize(draws.bai),
        bai_parabola=summarize(draws.bai_parabola),
        bci=summarize(draws.condition.bci),
        mass_kg=summarize(draws.condition.mass_kg),
        fraction_outside_fit_range=float(draws.condition.is_outside_fit_range.mean()),
    )


def uncertainty_budget(pixels: PixelMeasurements, focal_px: float, altitude_m: float,
                       hw: HWRatios, tail: str, errors: ErrorModel, num_draws: int,
                       rng: np.random.Generator, mass_model: MassModel = MassModel(),
                       bai_range: tuple[float, float] = BAI_RANGE,
                       progress: ProgressCallback | None = None,
                       cancel: threading.Event | None = None) -> dict[str, MonteCarloResult]:
    """One Monte Carlo per error source, all others off: what each contributes on its own
    (progress: draws done of all sources' draws)."""
    total = len(ERROR_SOURCES) * num_draws
    return {source: monte_carlo(pixels, focal_px, altitude_m, hw, tail, errors.only(source),
                                num_draws, rng, mass_model, bai_range,
                                part_of(progress, k * num_draws, total), cancel)
            for k, source in enumerate(ERROR_SOURCES)}
