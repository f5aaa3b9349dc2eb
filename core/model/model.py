"""The parametric dolphin model M(β, θ, P) as a stateless torch module.

Like smplx's ``SMPLLayer``, :class:`DolphinModel` holds only buffers (template data) and no
parameters: the fit owns β, θ and P and passes them to :meth:`DolphinModel.forward`.
"""

from dataclasses import dataclass

import torch
from torch import nn

from dolphinfit.core.model import lbs
from dolphinfit.core.model.profile_field import ProfileField
from dolphinfit.core.model.skeleton import fin_group_names
from dolphinfit.core.model.template import Template, load_template

NUM_SHAPE_PARAMS = 4  # log uniform scale + log scales along the part's x, y, z axes


@dataclass(frozen=True)
class ModelOutput:
    """Result of the forward model (metres, world frame: z up, water at z = 0)."""

    verts: torch.Tensor        # (T, V, 3) posed vertices
    joints: torch.Tensor       # (T, J, 3) posed joints
    rest_verts: torch.Tensor   # (V, 3) shaped vertices in the rest pose
    rest_joints: torch.Tensor  # (J, 3) shaped joints in the rest pose


class DolphinModel(nn.Module):
    """Per-part scaling and linear blend skinning of the procedural template."""

    def __init__(self, template: Template | None = None, dtype: torch.dtype = torch.float32):
        super().__init__()
        template = template if template is not None else load_template()
        self.joint_names = template.joint_names
        self.group_names = template.group_names
        self.joint_parents = [int(p) for p in template.joint_parents]
        self.rostrum_idx = template.rostrum_idx
        self.notch_idx = template.notch_idx
        self.register_buffer("rest_verts", torch.tensor(template.verts, dtype=dtype))
        self.register_buffer("faces", torch.tensor(template.faces, dtype=torch.int64))
        self.register_buffer("skin_weights", torch.tensor(template.skin_weights, dtype=dtype))
        self.register_buffer("rest_joints", torch.tensor(template.rest_joints, dtype=dtype))
        self.register_buffer("joint_axes", torch.tensor(template.joint_axes, dtype=dtype))
        self.register_buffer("joint_group", torch.tensor(template.joint_group, dtype=torch.int64))
        self.register_buffer("joint_mirror", torch.tensor(template.joint_mirror, dtype=torch.bool))
        self.register_buffer("group_parents",
                             torch.tensor(template.group_parents, dtype=torch.int64))
        self.register_buffer("station_rings",
                             torch.tensor(template.station_rings, dtype=torch.int64))
        self.register_buffer("fin_groups", torch.tensor(
            [name in fin_group_names() for name in template.group_names], dtype=torch.bool))
        self.profile_field = ProfileField(template, dtype)

    @property
    def num_groups(self) -> int:
        """M, the number of parts."""
        return len(self.group_names)

    def zero_params(self, num_frames: int) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """β (M, 4), θ (T, M, 3) and P (T, 3) that reproduce the template."""
        like = dict(dtype=self.rest_verts.dtype, device=self.rest_verts.device)
        return (torch.zeros(self.num_groups, NUM_SHAPE_PARAMS, **like),
                torch.zeros(num_frames, self.num_groups, 3, **like),
                torch.zeros(num_frames, 3, **like))

    def forward_rest(self, betas: torch.Tensor, profile: torch.Tensor | None = None
                     ) -> tuple[torch.Tensor, torch.Tensor]:
        """Shaped rest vertices (V, 3) and joints (J, 3) for β (M, 4) and, optionally, the
        profile field's (2, K) coefficients (profile_field.py; None: the template's)."""
        self._check_betas(betas)
        template_verts = (self.rest_verts if profile is None
                          else self.profile_field(self.rest_verts, profile))
        scales = lbs.part_scale_matrices(betas, self.joint_group, self.joint_axes)
        joints = lbs.scale_rest_joints(self.rest_joints, self.joint_parents, scales)
        verts = lbs.scale_rest_vertices(template_verts, self.rest_joints, joints, scales,
                                        self.skin_weights)
        return verts, joints

    def forward(self, betas: torch.Tensor, pose_aa: torch.Tensor, transl: torch.Tensor,
                profile: torch.Tensor | None = None) -> ModelOutput:
        """Posed meshes for β (M, 4), θ (T, M, 3) axis-angle per part, P (T, 3) metres and
        the optional profile field (2, K)."""
        rest_verts, rest_joints = self.forward_rest(betas, profile)
        return self.pose(rest_verts, rest_joints, pose_aa, transl)

    def pose(self, rest_verts: torch.Tensor, rest_joints: torch.Tensor, pose_aa: torch.Tensor,
             transl: torch.Tensor) -> ModelOutput:
        """Posed meshes of a shaped animal: its rest vertices (V, 3) and joints (J, 3) (from
        :meth:`forward_rest`), θ (T, M, 3) axis-angle per part and P (T, 3) metres."""
        if pose_aa.shape[1:] != (self.num_groups, 3) or transl.shape != (pose_aa.shape[0], 3):
            raise ValueError(f"pose_aa must be (T, {self.num_groups}, 3) and transl (T, 3); "
                             f"got {tuple(pose_aa.shape)} and {tuple(transl.shape)}")
        rotations = lbs.joint_rotations(pose_aa, self.joint_group, self.joint_mirror)
        global_rots, posed_joints = lbs.chain_transforms(rotations, rest_joints,
                                                         self.joint_parents, transl)
        verts = lbs.skin(rest_verts, rest_joints, global_rots, posed_joints, self.skin_weights)
        return ModelOutput(verts=verts, joints=posed_joints, rest_verts=rest_verts,
                           rest_joints=rest_joints)

    def _check_betas(self, betas: torch.Tensor) -> None:
        if betas.shape != (self.num_groups, NUM_SHAPE_PARAMS):
            raise ValueError(f"betas must be ({self.num_groups}, {NUM_SHAPE_PARAMS}); "
                             f"got {tuple(betas.shape)}")
