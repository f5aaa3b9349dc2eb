"""The fit's parameters (DESIGN.md §6: θ, β, P, albedo, F_water, light), where they start
and which of them each stage optimises."""

from dataclasses import dataclass, fields

import numpy as np
import torch

from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.data import FitData
from dolphinfit.core.fit.init import root_positions
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.profile_field import NUM_KNOTS
from dolphinfit.core.model.template import Template
from dolphinfit.core.render.shade import SGLight

INITIAL_F_WATER = 0.3


@dataclass
class SceneParams:
    """The tensors being optimised (DESIGN.md §6: θ, β, P, albedo, F_water, light)."""

    root_aa: torch.Tensor       # (T, 3)
    body_pose: torch.Tensor     # (T, M − 1, 3)
    transl: torch.Tensor        # (T, 3)
    log_scale: torch.Tensor     # () overall size, added to every part's uniform scale
    betas: torch.Tensor         # (M, 4) part shape around the overall size
    profile: torch.Tensor       # (2, K) profile field along the body (core.model.profile_field)
    albedo: torch.Tensor        # (Ht, Wt)
    f_water: torch.Tensor       # (3,)
    light_axes: torch.Tensor    # (K, 3)
    light_sharpness: torch.Tensor  # (K,)
    light_amplitude: torch.Tensor  # (K, 3)

    def tensors(self) -> dict[str, torch.Tensor]:
        """Name → tensor."""
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def snapshot(self) -> dict[str, torch.Tensor]:
        """Detached copies, to restore the best state."""
        return {name: t.detach().clone() for name, t in self.tensors().items()}

    def restore(self, snapshot: dict[str, torch.Tensor]) -> None:
        """Copy a snapshot back in place."""
        with torch.no_grad():
            for name, tensor in self.tensors().items():
                tensor.copy_(snapshot[name])

    def pose(self) -> torch.Tensor:
        """(T, M, 3) axis-angle per part."""
        return torch.cat([self.root_aa[:, None], self.body_pose], dim=1)

    def full_betas(self) -> torch.Tensor:
        """(M, 4) part log scales with the overall size."""
        return self.betas + torch.stack([self.log_scale] + [torch.zeros_like(self.log_scale)] * 3)

    def light(self) -> SGLight:
        """The light in its physical ranges."""
        return SGLight(self.light_axes / torch.linalg.vector_norm(self.light_axes, dim=-1,
                                                                  keepdim=True),
                       self.light_sharpness, self.light_amplitude)

    def project_to_valid(self) -> None:
        """Keep parameters in their domains after an optimiser step."""
        with torch.no_grad():
            self.albedo.clamp_(0.0, 1.0)
            self.f_water.clamp_(0.0, 1.0)
            self.light_sharpness.clamp_(min=0.05)
            self.light_amplitude.clamp_(min=0.0)
            self.light_axes.div_(torch.linalg.vector_norm(self.light_axes, dim=-1, keepdim=True))


def initial_params(data: FitData, model: DolphinModel, template: Template, config: FitConfig,
                    heading: np.ndarray, state, offset_xy: np.ndarray) -> SceneParams:
    transl = root_positions(state, heading, offset_xy, config.init_depth_m)
    num_frames, num_groups = data.num_frames, model.num_groups
    root = np.zeros((num_frames, 3))
    root[:, 2] = heading
    like = dict(dtype=torch.float32, device=data.device)
    light = SGLight.overhead_sun(**like)
    tensors = dict(
        root_aa=torch.tensor(root, **like),
        body_pose=torch.zeros(num_frames, num_groups - 1, 3, **like),
        transl=torch.tensor(transl, **like),
        log_scale=torch.tensor(state.log_scale, **like),
        betas=torch.zeros(num_groups, 4, **like),
        profile=torch.zeros(2, NUM_KNOTS, **like),
        albedo=torch.tensor(template.albedo / 255.0, **like),
        f_water=torch.full((3,), INITIAL_F_WATER, **like),
        light_axes=light.axes.clone(), light_sharpness=light.sharpness.clone(),
        light_amplitude=light.amplitude.clone())
    return SceneParams(**{k: v.requires_grad_() for k, v in tensors.items()})


def stage_groups(params: SceneParams, stage: str, config: FitConfig) -> list[dict]:
    """Adam parameter groups active in ``stage``, each with its learning rate."""
    lr = config.learning_rates
    groups = [{"params": [params.root_aa], "lr": lr.pose},
              {"params": [params.transl], "lr": lr.transl}]
    if stage in ("body", "shape"):
        groups.append({"params": [params.body_pose], "lr": lr.pose})
    if stage == "shape":
        # the overall size stays at its robust estimate from the masks until the frames the
        # pose stages cannot explain are set aside (dives would otherwise shrink it)
        shape = [params.log_scale, params.betas] + ([params.profile] if config.profile_field
                                                     else [])
        groups.append({"params": shape, "lr": lr.shape})
    if fits_appearance(stage):
        groups += [{"params": [params.albedo], "lr": lr.albedo},
                   {"params": [params.f_water], "lr": lr.water},
                   {"params": [params.light_axes, params.light_sharpness,
                               params.light_amplitude], "lr": lr.light}]
    return groups


def fits_appearance(stage: str) -> bool:
    """Whether ``stage`` fits albedo, water and light (the shape stage only)."""
    return stage == "shape"
