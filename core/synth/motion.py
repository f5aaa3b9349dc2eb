"""Swimming motion: a turning path, a dive and back, roll, a travelling fluke stroke, and the
lateral flex of a turn.

Returns the model's per-frame parameters: root translation P (T, 3) in metres and axis-angle
pose θ (T, M, 3) per part. The stroke is a dorso-ventral travelling wave down the tail stock
(rotations about each part's y axis, growing towards the flukes), as in cetacean swimming. In
a turn the body bends sideways with the path (rotations about each part's z axis): with
``turn_flex`` = 1 each joint turns by the path curvature times its spacing, so the midline
lies along the path's arc; larger values bend it more, as a dolphin does in a sharp turn.
"""

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.spatial.transform import Rotation

from dolphinfit.core.synth.config import SynthConfig

# Stroke amplitude (rad) and phase lag (rad) per part at stroke_amplitude = 1, head to flukes.
STROKE_PARTS: tuple[tuple[str, float, float], ...] = (
    ("head", 0.02, 0.0), ("tail0", 0.05, 0.3), ("tail1", 0.08, 0.8),
    ("tail2", 0.11, 1.3), ("tail3", 0.14, 1.8), ("tail4", 0.16, 2.3), ("flukes", 0.22, 2.9),
)
FLIPPER_POSE_RAD = (0.0, 0.05, 0.12)
# Lateral flex per part: its joint's distance from the parent joint as a fraction of body
# length (template v1; the flukes' to the blade's centre), and the side of the root it is on.
FLEX_PARTS: tuple[tuple[str, float, float], ...] = (
    ("thorax", 0.18, 1.0), ("head", 0.12, 1.0), ("tail0", 0.18, -1.0), ("tail1", 0.09, -1.0),
    ("tail2", 0.09, -1.0), ("tail3", 0.08, -1.0), ("tail4", 0.07, -1.0), ("flukes", 0.06, -1.0),
)


@dataclass(frozen=True)
class Motion:
    """Per-frame model parameters and what they mean."""

    time_s: np.ndarray      # (T,)
    transl: np.ndarray      # (T, 3) root position, metres, world frame
    pose_aa: np.ndarray     # (T, M, 3) axis-angle per part
    heading_rad: np.ndarray  # (T,) yaw of the body axis from world +x
    depth_m: np.ndarray     # (T,) root depth below the surface (positive down)


def swim(config: SynthConfig, group_names: tuple[str, ...], rng: np.random.Generator) -> Motion:
    """The clip's motion, centred in the frame, deterministic for ``rng``'s state."""
    t = np.arange(config.num_frames) / config.fps
    heading0 = (math.radians(config.heading_deg) if config.heading_deg is not None
                else rng.uniform(-math.pi, math.pi))
    heading = heading0 + math.radians(config.turn_deg_s) * (t - t.mean())
    step = config.speed_m_s / config.fps
    xy = np.cumsum(np.stack([np.cos(heading), np.sin(heading)], 1) * step, axis=0)
    xy -= 0.5 * (xy.min(0) + xy.max(0))

    depth = config.surface_depth_m + config.dive_depth_m * _dive_profile(t, config.duration_s)
    pitch = np.arctan2(np.gradient(depth, t) if len(t) > 1 else 0.0 * t, config.speed_m_s)
    phase = rng.uniform(0, 2 * math.pi)
    roll = math.radians(config.roll_deg) * np.sin(2 * math.pi * 0.3 * t + phase)
    root = Rotation.from_euler("ZYX", np.stack([heading, pitch, roll], 1)).as_rotvec()

    pose = np.zeros((len(t), len(group_names), 3))
    pose[:, group_names.index("root")] = root
    stroke = 2 * math.pi * config.stroke_hz * t + rng.uniform(0, 2 * math.pi)
    for part, amplitude, lag in STROKE_PARTS:
        pose[:, group_names.index(part), 1] = (config.stroke_amplitude * amplitude
                                               * np.sin(stroke - lag))
    if config.turn_flex:
        curvature = math.radians(config.turn_deg_s) / config.speed_m_s      # 1/m, + = left
        for part, spacing, side in FLEX_PARTS:
            pose[:, group_names.index(part), 2] = (side * config.turn_flex * curvature
                                                   * spacing * config.length_m)
    pose[:, group_names.index("flippers")] = FLIPPER_POSE_RAD
    transl = np.column_stack([xy, -depth])
    return Motion(time_s=t, transl=transl, pose_aa=pose, heading_rad=heading, depth_m=depth)


def companion(config: SynthConfig, target: Motion, group_names: tuple[str, ...],
              rng: np.random.Generator) -> Motion:
    """A second animal on the target's path, ``companion_offset_m`` to its left (negative:
    right) and ``companion_ahead_m`` ahead, with its own stroke and roll phases."""
    t = target.time_s
    heading0 = target.heading_rad[0] - math.radians(config.turn_deg_s) * (t[0] - t.mean())
    motion = swim(replace(config, heading_deg=math.degrees(heading0),
                          length_m=config.companion_length_m), group_names, rng)
    heading = motion.heading_rad
    forward = np.stack([np.cos(heading), np.sin(heading)], 1)
    left = np.stack([-np.sin(heading), np.cos(heading)], 1)
    xy = (motion.transl[:, :2] + config.companion_offset_m * left
          + config.companion_ahead_m * forward)
    return replace(motion, transl=np.column_stack([xy, motion.transl[:, 2]]))


def _dive_profile(t: np.ndarray, duration_s: float) -> np.ndarray:
    """0 at the surface, 1 at the bottom of one smooth dive over the clip's middle half."""
    phase = np.clip((t - 0.25 * duration_s) / (0.5 * duration_s), 0.0, 1.0)
    return np.sin(math.pi * phase) ** 2
