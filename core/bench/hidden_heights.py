"""How far a top view must miss a synthetic animal's volume, whatever the fit does.

A camera straight above sees the animal's widths, not its heights nor how full its sections
are; a fit takes both from its template (heights: its height/width ratios, or an HW table's;
sections: ellipses). The floor of a clip is the volume error of an estimate that has every
width exactly right and takes the heights and sections as the fit assumes them: the
elliptical volume (20 frustums, DESIGN.md §7) of the truth's widths with the fit's
height/width ratios, over that of the truth's widths and heights, times the area of the
fit's elliptical sections over the truth's (superellipse) ones, minus one. Fins are left out
of both. A fit whose error lies near its clip's floor has done what a top view allows.
"""

from dataclasses import dataclass

import numpy as np
import torch

from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.engine import fitted_template
from dolphinfit.core.measure.elliptical import TAIL_MEASURED, elliptical_volume
from dolphinfit.core.model.hw_from_model import hw_from_template, station_extents
from dolphinfit.core.model.sections import section_area_factor
from dolphinfit.core.model.template import load_template
from dolphinfit.core.synth.animal import synth_animal
from dolphinfit.core.synth.config import SynthConfig


@dataclass(frozen=True)
class TruthSections:
    """A synthetic animal's station widths and heights (S,), metres, and its sections'
    superellipse exponent."""

    width: np.ndarray
    height: np.ndarray
    section_exponent: float


def truth_sections(config: SynthConfig) -> TruthSections:
    """The sections of the animal ``config`` makes (rebuilt as ``make_clip`` builds it)."""
    _, model, betas = synth_animal(config, np.random.default_rng(config.seed))
    with torch.no_grad():
        rest = model.forward_rest(betas)[0]
    width, height = station_extents(rest.numpy(), model.station_rings.numpy())
    return TruthSections(width, height, config.section_exponent)


def hidden_height_floor(truth: TruthSections, fit_config: FitConfig) -> float:
    """The floor (module doc) of a fit made with ``fit_config`` on the animal ``truth``."""
    assumed = hw_from_template(fitted_template(load_template(), fit_config)).ratios
    ratio = (elliptical_volume(1.0, truth.width, assumed, TAIL_MEASURED)
             / elliptical_volume(1.0, truth.width, truth.height / truth.width, TAIL_MEASURED))
    return float(ratio / section_area_factor(truth.section_exponent) - 1.0)
