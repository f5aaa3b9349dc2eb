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

import numpy as np
import torch

from core.fit.config import FitConfig
from core.fit.engine import fitted_template
from core.io.json_file import read_json
from core.measure.elliptical import TAIL_MEASURED, elliptical_volume
from core.measure.mesh import station_profile
from core.model.sections import section_area_factor
from core.model.template import Template, load_template
from core.synth.clip import synth_animal
from core.synth.config import SynthConfig
from core.synth.files import ClipFiles


def station_hw(template: Template) -> np.ndarray:
    """(19,) height/width ratio of a template's rest mesh at the stations."""
    profile = station_profile(torch.as_tensor(template.verts),
                              torch.as_tensor(template.station_rings))
    return (profile.height / profile.width).numpy()


def hidden_height_floor(files: ClipFiles, fit_config: FitConfig) -> float:
    """The clip's floor (module doc) for a fit made with ``fit_config``."""
    config = SynthConfig.from_json(read_json(files.truth_json, "the clip's truth")["config"])
    _, model, betas = synth_animal(config, np.random.default_rng(config.seed))
    with torch.no_grad():
        rest = model.forward_rest(betas)[0]
    truth = station_profile(rest, model.station_rings)
    width, height = truth.width.numpy(), truth.height.numpy()
    assumed = station_hw(fitted_template(load_template(), fit_config))
    ratio = (elliptical_volume(1.0, width, assumed, TAIL_MEASURED)
             / elliptical_volume(1.0, width, height / width, TAIL_MEASURED))
    return float(ratio / section_area_factor(config.section_exponent) - 1.0)
