"""Part scaling in the rest pose and linear blend skinning, one pure function per step.

Shapes: T frames, V vertices, J joints, M parts (joint groups). All functions are
differentiable and take dtype and device from their inputs.

The forward model M(β, θ, P) (DESIGN.md §4):
  1. per-joint scale matrices from each part's β = (log s, log sx, log sy, log sz) along the
     part's local axes;
  2. scaled rest joints: each child rides on its parent's scaled bone;
  3. scaled rest vertices: each vertex scales about its joints, blended by skinning weight,
     so parts stay connected;
  4. per-joint rotations from each part's axis-angle (mirrored for right-side twins);
  5. chain transforms down the kinematic tree, root at its rest position + P;
  6. linear blend skinning.
"""

import torch

# Axis-angle of a right-side twin: reflecting y turns the rotation axis (a pseudovector)
# (x, y, z) into (−x, y, −z).
MIRROR_AXIS_ANGLE = (-1.0, 1.0, -1.0)
_SMALL_ANGLE_SQ = 1e-8


def part_scale_matrices(betas: torch.Tensor, joint_group: torch.Tensor,
                        joint_axes: torch.Tensor) -> torch.Tensor:
    """(J, 3, 3) scale matrices A_j = R_j · diag(s·sx, s·sy, s·sz) · R_jᵀ.

    betas: (M, 4) log scales per part; joint_group: (J,) int64; joint_axes: (J, 3, 3) with
    columns the part-local axes in world coordinates at rest.
    """
    log_scales = betas[joint_group, 0:1] + betas[joint_group, 1:4]
    scaled_axes = joint_axes * torch.exp(log_scales)[:, None, :]
    return scaled_axes @ joint_axes.transpose(1, 2)


def scale_rest_joints(rest_joints: torch.Tensor, parents: list[int],
                      scales: torch.Tensor) -> torch.Tensor:
    """(J, 3) joints after scaling: J'_root = J_root, J'_j = J'_p + A_p (J_j − J_p)."""
    joints = [rest_joints[0]]
    for j in range(1, len(parents)):
        p = parents[j]
        joints.append(joints[p] + scales[p] @ (rest_joints[j] - rest_joints[p]))
    return torch.stack(joints)


def scale_rest_vertices(rest_verts: torch.Tensor, rest_joints: torch.Tensor,
                        scaled_joints: torch.Tensor, scales: torch.Tensor,
                        weights: torch.Tensor) -> torch.Tensor:
    """(V, 3) vertices v' = Σ_j w_vj (J'_j + A_j (v − J_j))."""
    offsets = rest_verts[None, :, :] - rest_joints[:, None, :]          # (J, V, 3)
    per_joint = scaled_joints[:, None, :] + torch.einsum("jab,jvb->jva", scales, offsets)
    return torch.einsum("vj,jva->va", weights, per_joint)


def axis_angle_to_matrix(axis_angle: torch.Tensor) -> torch.Tensor:
    """(..., 3, 3) rotation matrices from axis-angle (Rodrigues), exact gradients at zero.

    R = I + a·K + b·K² with K = [ω]×, a = sin θ / θ, b = (1 − cos θ) / θ²; near θ = 0 the
    Taylor series of a and b are used so no square root of zero is differentiated.
    """
    theta_sq = (axis_angle * axis_angle).sum(-1, keepdim=True)[..., None]
    small = theta_sq < _SMALL_ANGLE_SQ
    safe_sq = torch.where(small, torch.ones_like(theta_sq), theta_sq)
    theta = torch.sqrt(safe_sq)
    a = torch.where(small, 1.0 - theta_sq / 6.0, torch.sin(theta) / theta)
    b = torch.where(small, 0.5 - theta_sq / 24.0, (1.0 - torch.cos(theta)) / safe_sq)
    x, y, z = axis_angle.unbind(-1)
    zero = torch.zeros_like(x)
    skew = torch.stack([zero, -z, y, z, zero, -x, -y, x, zero], dim=-1)
    skew = skew.reshape(axis_angle.shape[:-1] + (3, 3))
    eye = torch.eye(3, dtype=axis_angle.dtype, device=axis_angle.device)
    return eye + a * skew + b * (skew @ skew)


def joint_rotations(pose_aa: torch.Tensor, joint_group: torch.Tensor,
                    joint_mirror: torch.Tensor) -> torch.Tensor:
    """(T, J, 3, 3) local rotation of each joint from its part's axis-angle (T, M, 3)."""
    mirror = torch.tensor(MIRROR_AXIS_ANGLE, dtype=pose_aa.dtype, device=pose_aa.device)
    signs = torch.where(joint_mirror[:, None], mirror, torch.ones_like(mirror))
    return axis_angle_to_matrix(pose_aa[:, joint_group] * signs)


def chain_transforms(rotations: torch.Tensor, joints: torch.Tensor, parents: list[int],
                     transl: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Global rotations (T, J, 3, 3) and posed joint positions (T, J, 3).

    The root sits at its rest position + transl (T, 3); each child at
    pos_p + R_p (J_j − J_p) with R_j = R_p · rot_j.
    """
    rots = [rotations[:, 0]]
    positions = [joints[0] + transl]
    for j in range(1, len(parents)):
        p = parents[j]
        rots.append(rots[p] @ rotations[:, j])
        positions.append(positions[p] + torch.einsum("tab,b->ta", rots[p], joints[j] - joints[p]))
    return torch.stack(rots, dim=1), torch.stack(positions, dim=1)


def skin(verts: torch.Tensor, joints: torch.Tensor, global_rots: torch.Tensor,
         posed_joints: torch.Tensor, weights: torch.Tensor) -> torch.Tensor:
    """(T, V, 3) posed vertices v = Σ_j w_vj (R_j (v − J_j) + pos_j).

    verts: (V, 3) and joints: (J, 3) in the scaled rest pose; global_rots: (T, J, 3, 3);
    posed_joints: (T, J, 3); weights: (V, J).
    """
    num_frames, num_joints = global_rots.shape[:2]
    offsets = posed_joints - torch.einsum("tjab,jb->tja", global_rots, joints)   # (T, J, 3)
    transforms = torch.cat([global_rots, offsets[..., None]], dim=-1)            # (T, J, 3, 4)
    # one matrix product blends every frame's transforms, (T·12, J) @ (J, V); the 3×4
    # products with the vertices are written out over unbound columns (einsum's tiny batched
    # products, or indexing, whose backward fills a whole tensor per column, are slower)
    blended = transforms.permute(0, 2, 3, 1).reshape(-1, num_joints) @ weights.T
    col_x, col_y, col_z, col_1 = blended.reshape(num_frames, 3, 4, -1).unbind(2)  # (T, 3, V)
    x, y, z = verts.T
    return (col_x * x + col_y * y + col_z * z + col_1).transpose(1, 2).contiguous()
