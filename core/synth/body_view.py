"""A synthetic clip's animal at one frame with its fins taken off, as the clip's camera saw it:
the truth a width is scored against, since a person measures the body, not the flippers,
the dorsal fin or the fluke lobes beside it.

The mask is made as the clip's true masks are (``core.synth.recorder``): the scene rendered at
the clip's supersampled size, the share of each delivered pixel covered by the body's faces,
then the majority rule. The surface's ripples, which shift submerged parts by a fraction of a
pixel, are left out.
"""

import numpy as np
import torch

from dolphinfit.core.synth.animal import swimming_animal
from dolphinfit.core.synth.clip import scene_appearance, scene_intrinsics
from dolphinfit.core.synth.compose import layer_coverage, render_layer
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.recorder import true_mask


def fin_free_faces(template) -> np.ndarray:
    """(F,) bool: the template's faces with no corner on a fin (flippers, dorsal fin, flukes)."""
    is_fin = np.zeros(len(template.verts), bool)
    for vertices in template.fin_vertices.values():
        is_fin[vertices] = True
    return ~is_fin[np.asarray(template.faces)].any(axis=1)


def body_mask(config: SynthConfig, frame_idx: int) -> np.ndarray:
    """(H, W) bool at the clip's size: the pixels the animal's body without its fins covers
    more than half of at ``frame_idx``."""
    animal = swimming_animal(config, np.random.default_rng(config.seed))
    template, model = animal.template, animal.model
    body = np.asarray(fin_free_faces(template))
    intrinsics = scene_intrinsics(config)
    layer = render_layer(animal.verts[frame_idx:frame_idx + 1], model.faces,
                         scene_appearance(template, config), intrinsics,
                         float(animal.altitude_m[frame_idx]), config.effects.refraction, None,
                         (torch.as_tensor(body),))
    share = layer_coverage(layer, intrinsics.height_px, intrinsics.width_px, 0)
    return true_mask(share, (config.width_px, config.height_px))
