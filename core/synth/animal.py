"""What a synthetic clip shows, whichever renderer draws it: the animal (template, model, part
scales), its motion and posed vertices, the drone's altitudes and a companion. Drawn from the
clip's seed in a fixed order, so every renderer shows the same scene."""

import math
from dataclasses import dataclass

import numpy as np
import torch

from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.sections import reshape_sections
from dolphinfit.core.model.template import Template, load_template
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.foreign import foreign_template
from dolphinfit.core.synth.motion import Motion, companion, swim
from dolphinfit.core.synth.shape import draw_hw, random_betas, subdivide, warp_profiles


@dataclass(frozen=True, eq=False)
class SwimmingAnimal:
    """The clip's animal and its swim: posed vertices (T, V, 3) float32, world metres."""

    template: Template
    model: DolphinModel
    betas: torch.Tensor
    motion: Motion
    altitude_m: np.ndarray     # (T,) the drone's height above the water
    verts: torch.Tensor


def swimming_animal(config: SynthConfig, rng: np.random.Generator) -> SwimmingAnimal:
    """The animal, its motion and the altitudes, drawn from ``rng`` first in this order."""
    template, model, betas = synth_animal(config, rng)
    motion = swim(config, model.group_names, rng)
    altitude = (config.altitude_m + config.altitude_drift_m
                * np.sin(2 * math.pi * motion.time_s / (1.3 * config.duration_s)
                         + rng.uniform(0, 2 * math.pi)))
    return SwimmingAnimal(template, model, betas, motion, altitude, posed(model, betas, motion))


def posed(model: DolphinModel, betas: torch.Tensor, motion: Motion) -> torch.Tensor:
    """(T, V, 3) float32 vertices of the animal through its motion."""
    with torch.no_grad():
        return model(betas, torch.as_tensor(motion.pose_aa),
                     torch.as_tensor(motion.transl)).verts.to(torch.float32)


def synth_animal(config: SynthConfig, rng: np.random.Generator
                 ) -> tuple[Template, DolphinModel, torch.Tensor]:
    """The clip's animal: its template (heights, sections, warp, finer mesh as configured),
    the model of it and its part scales; draws from ``rng`` first, as ``make_clip`` does."""
    template = foreign_template(_body(config), config.body)
    if config.effects.profile_warp:
        template = warp_profiles(template, rng, tie_heights=config.hw_table is not None)
    if config.effects.finer_mesh:
        template = subdivide(template)
    model = DolphinModel(template, dtype=torch.float64)
    betas = random_betas(model, config.length_m, config.shape_sd, rng,
                         tie_heights=config.hw_table is not None)
    return template, model, betas


def _body(config: SynthConfig) -> Template:
    """The template with the configured heights and sections (core/model/sections.py)."""
    template = load_template()
    if config.hw_table is None and config.section_exponent == 2.0:
        return template
    station_hw = None
    if config.hw_table is not None:
        station_hw = draw_hw(load_hw_preset(config.hw_table),
                             np.random.default_rng([config.seed, 4]))
    return reshape_sections(template, station_hw, config.section_exponent)


def companion_animal(config: SynthConfig, model: DolphinModel, target: Motion,
                     rng: np.random.Generator) -> tuple[Motion | None, torch.Tensor | None]:
    """The second animal's motion and posed vertices (T, V, 3), or None when alone."""
    if config.companion_offset_m is None:
        return None, None
    betas = random_betas(model, config.companion_length_m, config.shape_sd, rng,
                         tie_heights=config.hw_table is not None)
    motion = companion(config, target, model.group_names, rng)
    return motion, posed(model, betas, motion)
