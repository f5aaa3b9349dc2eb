"""Monte Carlo uncertainty of the model-based fit: length, volume, BCI and mass.

A fit is too slow to rerun per draw, so each draw perturbs the fitted animal the way each
error source would have (first order in the error), and reruns body condition and mass:

- **Altitude and camera** (the elliptical method's ``ErrorModel`` fields): the metric scale
  m/px = altitude / focal length in pixels is off by their ratio, so lengths scale by it and
  the volume by its cube.
- **Outline**: the masks the fit matched lie ``δ`` pixels outside (+) or inside (−) the
  animal's true outline, one ``δ`` per clip (a bias of the segmenter on that water, not
  noise: it does not average out over frames), its SD a share of the frame's width
  (``OUTLINE_SD_OF_WIDTH``) or of the blur of the animal's edge (``OUTLINE_SD_PER_BLUR``),
  whichever is larger. Every station's width grows by 2δ, its height
  with it (the fit ties heights to widths), and the length by 2δ (rostrum tip and fluke
  notch). Checked against fits on the suite's true masks grown by 1.2 px all round: this
  model gives +24.6 % and +38.6 % of volume where the fit gave +19.5 % and +31.9 %
  (`grey_green`, `grey_green_high`); on masks shrunk by 0.84 px it gives a little less than
  the fit (docs/explanation/uncertainty.md).
- **Hidden heights**: the heights a top view cannot see come from the HW table; each draw
  moves every station's ratio by one shared z times its SD, as the elliptical method's draws
  do (``uncertainty`` module doc).

The volume of a draw is the fitted volume times the change of Σ width × height over the
stations (elliptical sections at equal spacing); fins and flukes follow the body.
"""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.measure.condition import MassModel, body_condition
from dolphinfit.core.measure.hw_ratios import HWRatios
from dolphinfit.core.measure.uncertainty import ErrorModel, Summary, summarize, summary_json

# The outline bias of the product's masks, one SD, as a share of the frame's width: the root
# mean square of the per-clip outline offsets of the default back-end on the bench suite
# (`dolphinfit bench masks`) was 0.31 px at 1920 px wide (−0.61 … +0.37 px over 12 clips) and
# 0.74 px at 3840 (−1.66 … +0.48 px): the larger share, so 0.36 px at 1080p and 0.73 px at
# 4K. The errors grow with the frame (foam, glitter and faint ends are scene-sized, not pixel-
# sized). Measured on synthetic clips only: real water may do worse (provisional).
OUTLINE_SD_OF_WIDTH = 1.9e-4
# The same offsets against the blur index of the animal's edge (core.measure.edge_blur, on the
# true masks of the scored frames): their root mean square over the index was 0.35 on the
# tuning split (12 clips at 1080p, index 0.55–1.14) and 0.28 on the held-out split (8 clips,
# two of them 720p frames of 5K footage with 13–14 px wide animals). Downscaled or soft footage
# blurs the edge in pixels while the frame's width shrinks: the frame-width rule then claims an
# outline sharper than the image (0.14 px on a 719-px wide clip) where this one does not.
OUTLINE_SD_PER_BLUR = 0.35
DEFAULT_FIT_DRAWS = 4000


def outline_sd_px(frame_width_px: int, edge_blur_px: float = float("nan")) -> float:
    """The default outline SD in pixels of a frame ``frame_width_px`` wide whose animal's edge
    has the blur index ``edge_blur_px`` (NaN: not measured): the larger of the two rules, each
    measured on the bench's clips, so neither a sharp large frame nor a soft small one is
    taken for more precise than its own rule says."""
    by_width = OUTLINE_SD_OF_WIDTH * frame_width_px
    if not np.isfinite(edge_blur_px):
        return by_width
    return max(by_width, OUTLINE_SD_PER_BLUR * edge_blur_px)


@dataclass(frozen=True, eq=False)
class FitInterval:
    """Mean, SD and central 95 % interval of a fit's figures over ``num_draws`` draws."""

    num_draws: int
    errors: ErrorModel      # its digitisation SD unused: the fit has no clicks
    outline_sd_px: float
    length_m: Summary
    volume_m3: Summary
    bci: Summary
    density_kg_m3: Summary
    mass_kg: Summary

    def to_json(self) -> dict:
        """The draws' summaries and what they assumed."""
        errors = self.errors
        return {"num_draws": self.num_draws, "outline_sd_px": self.outline_sd_px,
                "errors": {"altitude_sd_fraction": errors.altitude_sd_fraction,
                           "focal_sd_fraction": errors.focal_sd_fraction,
                           "hw_sd_scale": errors.hw_sd_scale},
                **{name: summary_json(getattr(self, name))
                   for name in ("length_m", "volume_m3", "bci", "density_kg_m3", "mass_kg")}}


def fit_interval(length_m: float, volume_m3: float, widths_m: np.ndarray,
                 heights_m: np.ndarray, m_per_px: float, errors: ErrorModel, hw: HWRatios,
                 rng: np.random.Generator, outline_sd_px: float,
                 mass_model: MassModel = MassModel(),
                 num_draws: int = DEFAULT_FIT_DRAWS) -> FitInterval:
    """The fit's figures over ``num_draws`` draws of the error sources (module doc).

    widths_m, heights_m: (S,) the fitted rest mesh's extents at the stations
    (``hw_from_model.station_extents``); m_per_px: the clip's nominal scale at the animal, in
    the pixels of ``outline_sd_px`` (the frame's own: ``outline_sd_px(width)``).
    """
    if num_draws < 2:
        raise ValueError(f"num_draws must be at least 2, got {num_draws}")
    widths, heights = np.asarray(widths_m, float), np.asarray(heights_m, float)
    if not (np.all(widths > 0) and np.all(heights > 0) and m_per_px > 0 and length_m > 0
            and volume_m3 > 0 and outline_sd_px >= 0):
        raise ValueError("fit_interval needs positive widths, heights, scale, length, volume "
                         "and a non-negative outline SD")
    scale = ((1 + rng.normal(0.0, errors.altitude_sd_fraction, num_draws))
             / (1 + rng.normal(0.0, errors.focal_sd_fraction, num_draws)))
    grown_m = 2 * m_per_px * rng.normal(0.0, outline_sd_px, num_draws)
    ratios, ratio_sd = hw.completed()
    relative_sd = errors.hw_sd_scale * ratio_sd / ratios
    height_factor = 1 + rng.normal(0.0, 1.0, (num_draws, 1)) * relative_sd
    drawn_widths = np.maximum(widths + grown_m[:, None], 0.0)
    drawn_heights = heights * drawn_widths / widths * height_factor
    section_change = (drawn_widths * drawn_heights).sum(1) / (widths * heights).sum()
    lengths = scale * (length_m + grown_m)
    volumes = scale ** 3 * volume_m3 * section_change
    condition = body_condition(lengths, volumes, mass_model)
    return FitInterval(num_draws=num_draws, errors=errors, outline_sd_px=outline_sd_px,
                       length_m=summarize(lengths), volume_m3=summarize(volumes),
                       bci=summarize(condition.bci),
                       density_kg_m3=summarize(condition.density_kg_m3),
                       mass_kg=summarize(condition.mass_kg))
