"""A fitted shape posed at one pose of its motion (core.fit.motion), for drawing over a frame.

The fit's hidden heights (core.model.sections) and profile field move the rest vertices only,
never the joints, so a fit's shaped rest mesh and its betas, posed on the default template's
skeleton and skin weights, give the fit's own posed mesh at a fitted frame.
"""

from functools import lru_cache

import numpy as np
import torch

from dolphinfit.core.fit.motion import FramePose
from dolphinfit.core.model.model import DolphinModel


@lru_cache(maxsize=1)
def _model() -> DolphinModel:
    """The default template's model in float64, built once (about 20 ms)."""
    return DolphinModel(dtype=torch.float64)


def posed_mesh(rest_verts: np.ndarray, betas: np.ndarray, pose: FramePose) -> np.ndarray:
    """(V, 3) float64 vertices, metres, world frame: a fit's shaped rest mesh rest_verts
    (V, 3), whose joints its betas (M, 4) place, posed at ``pose``."""
    model = _model()
    with torch.no_grad():
        _, rest_joints = model.forward_rest(_float64(betas))
        posed = model.pose(_float64(rest_verts), rest_joints, _float64(pose.pose_aa[None]),
                           _float64(pose.transl[None]))
    return posed.verts[0].numpy()


def _float64(array: np.ndarray) -> torch.Tensor:
    return torch.as_tensor(np.asarray(array, np.float64))
