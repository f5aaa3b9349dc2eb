"""A fitted animal's 95 % intervals (core.measure.fit_uncertainty): from its rest mesh at a
given scale and HW table, and for a finished run at the scale of the clip's own pixels, on
the HW table it assumed."""

import numpy as np

from dolphinfit.core.fit.pipeline import FitRun
from dolphinfit.core.fit.result import FitResult
from dolphinfit.core.measure.condition import MassModel
from dolphinfit.core.measure.fit_uncertainty import (
    DEFAULT_FIT_DRAWS, FitInterval, fit_interval, outline_sd_px,
)
from dolphinfit.core.model.hw_from_model import station_extents
from dolphinfit.core.measure.hw_ratios import HWRatios, load_hw_preset
from dolphinfit.core.model.hw_spec import resolve_hw
from dolphinfit.core.measure.uncertainty import ErrorModel
from dolphinfit.core.model.template import load_template

INTERVAL_SEED = 0  # the draws are seeded: a fit reports the same interval every time


def result_interval(result: FitResult, m_per_px: float, errors: ErrorModel, hw: HWRatios,
                    outline_sd: float, mass_model: MassModel = MassModel(),
                    num_draws: int = DEFAULT_FIT_DRAWS) -> FitInterval:
    """The Monte Carlo of a fit's figures, from its rest mesh's station extents: ``m_per_px``
    metres in a pixel of ``outline_sd`` (the outline SD)."""
    widths, heights = station_extents(result.rest_verts, load_template().station_rings)
    return fit_interval(result.length_m, result.volume_m3, widths, heights, m_per_px, errors,
                        hw, np.random.default_rng(INTERVAL_SEED), outline_sd, mass_model,
                        num_draws)


def run_interval(run: FitRun, errors: ErrorModel,
                 outline_sd: float | None = None) -> FitInterval:
    """The fit's Monte Carlo with ``errors`` and an outline SD of ``outline_sd`` pixels of
    the clip (default: ``outline_sd_px`` of its width and its edge's blur); metres per pixel
    at the median
    altitude of the fitted frames; its HW table's SDs (the default table's when it kept the
    template's own heights, which state none)."""
    camera, width = run.data.camera, run.clip.width_px
    fitted_m_per_px = camera.intrinsics.gsd_m_per_px(float(camera.altitude_m.median()))
    m_per_px = fitted_m_per_px / run.data.clip_px_per_px  # the fit's pixels may be larger
    table = run.result.config.hw_table
    hw = load_hw_preset() if table is None else resolve_hw(table)
    return result_interval(run.result, m_per_px, errors, hw,
                           outline_sd_px(width, run.result.edge_blur_px)
                           if outline_sd is None else outline_sd)
