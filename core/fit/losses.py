"""The loss terms of the fit, each a pure function returning a scalar tensor.

Names and weights follow DESIGN.md §6 (the paper's table). Shapes: T frames, M parts,
H × W pixels.
"""

import torch


def soft_iou_loss(soft: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
    """Σ_t (1 − Σ s·t / Σ (s + t − s·t)) over frames (T, H, W) (Kaolin's mask_iou, summed)."""
    inter = (soft * target).sum((1, 2))
    union = (soft + target - soft * target).sum((1, 2)).clamp(min=1e-6)
    return (1.0 - inter / union).sum()


def rgb_loss(colour: torch.Tensor, frame: torch.Tensor, image: torch.Tensor,
             target: torch.Tensor, num_frames: int) -> torch.Tensor:
    """Σ_t mean squared colour error over the pixels covered by the render and the target.

    Per covered pixel (C,): rendered ``colour`` (C, 3), its ``frame`` (C,) in 0 … T − 1, the
    image's colour there (C, 3) and the target mask's value (C,); only covered pixels are
    ever touched (a tenth of an ROI), never the whole image.
    """
    both = (target > 0.5).to(colour.dtype)
    error = ((colour - image) ** 2).sum(-1) * both
    like = dict(dtype=colour.dtype, device=colour.device)
    per_frame = torch.zeros(num_frames, **like).index_add(0, frame, error)
    count = torch.zeros(num_frames, **like).index_add(0, frame, both)
    return (per_frame / count.clamp(min=1.0)).sum()


def pose_prior(body_pose: torch.Tensor) -> torch.Tensor:
    """Mean over frames of the squared norm of the body parts' rotations (T, M − 1, 3)."""
    return (body_pose ** 2).sum((1, 2)).mean()


def pitch_bend_prior(body_pose: torch.Tensor, spine: torch.Tensor) -> torch.Tensor:
    """Σ over the ``spine`` parts (M − 1,) bool of their rotation about the lateral (y) axis
    averaged over frames, squared (body_pose: T, M − 1, 3). A stroking tail bends up and down
    about straight, so its bend averages out over a clip; a lasting bend is what a top view
    cannot tell from a shorter animal."""
    return (body_pose[:, spine, 1].mean(0) ** 2).sum()


def scale_prior(betas: torch.Tensor) -> torch.Tensor:
    """Squared norm of the part log scales (M, 4)."""
    return (betas ** 2).sum()


def scale_axes_prior(betas: torch.Tensor) -> torch.Tensor:
    """Σ_k (β_k,x − β_k,y)² + (β_k,y − β_k,z)²: axes of a part scale together (the paper)."""
    return ((betas[:, 1] - betas[:, 2]) ** 2 + (betas[:, 2] - betas[:, 3]) ** 2).sum()


def profile_prior(coefficients: torch.Tensor) -> torch.Tensor:
    """Squared norm of the profile field's coefficients (2, K)."""
    return (coefficients ** 2).sum()


def profile_smoothness(coefficients: torch.Tensor) -> torch.Tensor:
    """Σ of squared second differences of each row of the profile field (2, K) from knot to
    knot: bends, not steps, cost."""
    return ((coefficients[:, 2:] - 2 * coefficients[:, 1:-1] + coefficients[:, :-2]) ** 2).sum()


def scale_smooth_prior(betas: torch.Tensor, group_parents: torch.Tensor) -> torch.Tensor:
    """Σ_k ‖β_k − β_parent(k)‖² over parts with a parent."""
    child = group_parents >= 0
    return ((betas[child] - betas[group_parents[child]]) ** 2).sum()


def smoothness(values: torch.Tensor, order: int, frame_ratio: float) -> torch.Tensor:
    """Mean squared first (order 1) or second (order 2) difference over frames of (T, …).

    Differences are rescaled to the reference frame interval: ``frame_ratio`` = reference
    interval / actual interval, raised to ``order``, so a weight means the same motion
    penalty at any fitting rate.
    """
    diff = values
    for _ in range(order):
        if diff.shape[0] < 2:
            return values.sum() * 0.0
        diff = diff[1:] - diff[:-1]
    diff = diff * frame_ratio ** order
    return (diff ** 2).reshape(diff.shape[0], -1).sum(1).mean()


def rotation_smoothness(rotations: torch.Tensor, order: int, frame_ratio: float) -> torch.Tensor:
    """Smoothness of root orientations (T, 3, 3) on the matrices (no axis-angle wrap-around)."""
    return smoothness(rotations.reshape(rotations.shape[0], 9), order, frame_ratio)


def vertical_motion(transl: torch.Tensor, forward_z: torch.Tensor, time_s: torch.Tensor,
                    v_surf_m_s: float, v_dive_m_s: float) -> torch.Tensor:
    """The paper's depth nudge: P_z moves up at v_surf while the rostrum points up, down at
    v_dive while it points down; mean squared deviation from that vertical step."""
    if transl.shape[0] < 2:
        return transl.sum() * 0.0
    dt = time_s[1:] - time_s[:-1]
    pitch = forward_z[:-1].detach()
    speed = v_surf_m_s * pitch.clamp(min=0.0) + v_dive_m_s * pitch.clamp(max=0.0)
    step = transl[1:, 2] - transl[:-1, 2]
    return ((step - speed * dt) ** 2).mean()


def glide_prior(transl: torch.Tensor, forward: torch.Tensor,
                time_s: torch.Tensor) -> torch.Tensor:
    """Mean squared deviation ((m/s)²) of the root's vertical speed between adjacent frames
    from a glide along the body axis: an animal swims where it points, so it rises or sinks
    at its horizontal speed times the slope of its axis (``forward`` (T, 3), the root's
    x axis; averaged over the two frames). A top view sees no pitch directly, and without
    it the fit tilted a longer animal nose down at a level depth to match a short silhouette
    (the tail 0.5–0.9 m above the water for three seconds)."""
    if transl.shape[0] < 2:
        return transl.sum() * 0.0
    step = transl[1:] - transl[:-1]
    axis = 0.5 * (forward[1:] + forward[:-1])
    slope = axis[:, 2] / torch.linalg.vector_norm(axis[:, :2], dim=-1).clamp(min=1e-3)
    horizontal = torch.linalg.vector_norm(step[:, :2], dim=-1)
    dt = (time_s[1:] - time_s[:-1]).clamp(min=1e-6)
    return (((step[:, 2] - horizontal * slope) / dt) ** 2).mean()


def depth_prior(transl: torch.Tensor, depth_m: float) -> torch.Tensor:
    """Mean squared deviation (m²) of the root's depth below the surface (world z = 0) from
    ``depth_m``, over frames: silhouettes alone cannot tell a deeper animal from a larger
    one, so without it the depth drifts and takes the overall size with it."""
    return ((transl[:, 2] + depth_m) ** 2).mean()


def direction_loss(forward_xy: torch.Tensor, transl: torch.Tensor) -> torch.Tensor:
    """Mean of 1 − cos(angle between heading and direction of motion), adjacent frames."""
    if transl.shape[0] < 2:
        return transl.sum() * 0.0
    motion = transl[1:, :2] - transl[:-1, :2]
    motion = motion / torch.linalg.vector_norm(motion, dim=-1, keepdim=True).clamp(min=1e-6)
    heading = forward_xy[:-1] / torch.linalg.vector_norm(forward_xy[:-1], dim=-1,
                                                         keepdim=True).clamp(min=1e-6)
    return (1.0 - (heading * motion).sum(-1)).mean()
