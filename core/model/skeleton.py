"""Skeleton of the template: joints, parts (joint groups) and smooth skinning weights.

The spine is a chain from the rostrum to the fluke root with the root near the middle:
head ← thorax ← root → tail0 → … → tail4 (fluke root), five tail-stock joints for the stroke.
Fins hang off it: flippers on the thorax, dorsal fin on the root, flukes on tail4. Left/right
fins share one part (group) and mirror its rotation (DESIGN.md §4).

Body vertices are weighted by their position t along the body (fraction of BL): each spine
joint owns the stretch between itself and its child, and neighbouring stretches blend over
±``BLEND_HALF_WIDTH`` with a smoothstep, so the weights are smooth, non-negative and sum to
one exactly (a telescoping sum).
"""

from dataclasses import dataclass

import numpy as np

BLEND_HALF_WIDTH = 0.02   # fraction of BL on each side of a spine joint
FIN_BLEND_LAYERS = 0.35   # fin weights reach 1 at this fraction of the fin's span


@dataclass(frozen=True)
class JointSpec:
    """One joint: its parent, its part (group), and where it sits."""

    name: str
    parent: str | None
    group: str
    spine_t: float | None = None   # position along the body, for spine joints
    fin: str | None = None         # fin name, for fin joints (pivot at the fin's base)
    mirror: bool = False           # right-side twin of a left fin


JOINTS: tuple[JointSpec, ...] = (
    JointSpec("root", None, "root", spine_t=0.40),
    JointSpec("thorax", "root", "thorax", spine_t=0.22),
    JointSpec("head", "thorax", "head", spine_t=0.10),
    JointSpec("tail0", "root", "tail0", spine_t=0.58),
    JointSpec("tail1", "tail0", "tail1", spine_t=0.67),
    JointSpec("tail2", "tail1", "tail2", spine_t=0.76),
    JointSpec("tail3", "tail2", "tail3", spine_t=0.84),
    JointSpec("tail4", "tail3", "tail4", spine_t=0.91),
    JointSpec("dorsal_fin", "root", "dorsal_fin", fin="dorsal_fin"),
    JointSpec("flipper_l", "thorax", "flippers", fin="flipper"),
    JointSpec("flipper_r", "thorax", "flippers", fin="flipper", mirror=True),
    JointSpec("fluke_l", "tail4", "flukes", fin="fluke"),
    JointSpec("fluke_r", "tail4", "flukes", fin="fluke", mirror=True),
)

ROOT_T = JOINTS[0].spine_t

# Spine stretches in order from the rostrum: (joint name, posterior boundary t). Each
# non-root joint sits on the boundary it shares with its parent's stretch.
_SPINE_STRETCHES: tuple[tuple[str, float], ...] = (
    ("head", 0.10), ("thorax", 0.22), ("root", 0.58), ("tail0", 0.67), ("tail1", 0.76),
    ("tail2", 0.84), ("tail3", 0.91), ("tail4", np.inf),
)


def joint_index(name: str) -> int:
    """Index of a joint by name."""
    return next(i for i, joint in enumerate(JOINTS) if joint.name == name)


def group_names() -> tuple[str, ...]:
    """Part names in order of first appearance (group 0 is the root)."""
    return tuple(dict.fromkeys(joint.group for joint in JOINTS))


def fin_group_names() -> frozenset[str]:
    """The parts that are fins (dorsal fin, flippers, flukes)."""
    return frozenset(joint.group for joint in JOINTS if joint.fin is not None)


def smoothstep(x: np.ndarray) -> np.ndarray:
    """0 below −1, 1 above +1, C¹-smooth in between."""
    u = np.clip((x + 1.0) * 0.5, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def spine_weights(t: np.ndarray) -> np.ndarray:
    """(N, J) skinning weights of body points at positions ``t`` (fractions of BL)."""
    t = np.asarray(t, dtype=np.float64)
    weights = np.zeros((len(t), len(JOINTS)))
    lower = np.ones_like(t)
    for name, boundary in _SPINE_STRETCHES:
        upper = smoothstep((t - boundary) / BLEND_HALF_WIDTH) if np.isfinite(boundary) else 0.0
        weights[:, joint_index(name)] = lower - upper
        lower = upper
    return weights


def fin_weights(base_weights: np.ndarray, fraction: np.ndarray, joint: int) -> np.ndarray:
    """(N, J) weights of fin vertices from their base's weights and span ``fraction``."""
    share = smoothstep(2.0 * np.minimum(np.asarray(fraction) / FIN_BLEND_LAYERS, 1.0) - 1.0)
    weights = (1.0 - share)[:, None] * base_weights
    weights[:, joint] += share
    return weights
