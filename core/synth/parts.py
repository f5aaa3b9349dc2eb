"""The face sets of the body parts that decide length: the flukes and the rostrum.

flukes: faces whose corners are skinned mostly (mean weight > ½) to the "flukes" part;
rostrum: faces whose centroid lies within ``ROSTRUM_FRACTION`` of body length of the rostrum
tip, on the shaped rest mesh.
"""

import torch

from dolphinfit.core.measure.mesh import body_length
from dolphinfit.core.model.model import DolphinModel

PART_NAMES = ("flukes", "rostrum")
ROSTRUM_FRACTION = 0.10


def part_faces(model: DolphinModel, betas: torch.Tensor) -> tuple[torch.Tensor, ...]:
    """(F,) bool face sets in the order of ``PART_NAMES``."""
    flukes_group = model.group_names.index("flukes")
    weight = model.skin_weights[:, model.joint_group == flukes_group].sum(1)
    flukes = weight[model.faces].mean(1) > 0.5
    with torch.no_grad():
        rest = model.forward_rest(betas)[0]
        length = body_length(rest, model.rostrum_idx, model.notch_idx)
    centroid = rest[model.faces].mean(1)
    to_tip = torch.linalg.vector_norm(centroid - rest[model.rostrum_idx], dim=-1)
    return flukes, to_tip < ROSTRUM_FRACTION * length
