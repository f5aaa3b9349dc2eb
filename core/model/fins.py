"""Fins of the template, extruded from one-quad-wide strips of the body tube.

A fin's base is a strip of body quads between two adjacent ring vertices (side A and side B)
over a run of rings. The strip's quads are removed and replaced by walls that rise through
``num_layers`` loops to a thin cap, which keeps the mesh one closed, consistently wound
manifold without booleans. Each loop is a planform section: leading and trailing edge along
the chord direction, offset along the span direction, thickness along the fin normal; the
base's own shape is blended out over the first layers so the fin grows smoothly from the body.

Proportions (fractions of BL) follow reference/morphometrics.md §5–§6: dorsal fin base
0.425–0.55 and height 0.10; flipper insertion at 0.225, length 0.16; flukes from 0.875 with a
half span of 0.12 from the body axis (span 0.24) and tips trailing the notch by 2.5 % BL.
"""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.model.body import FLIPPER_PAIR, LATERAL_PAIR, Attachment


@dataclass(frozen=True)
class FinSpec:
    """Planform of one fin, for the animal's left side (or the midline)."""

    name: str
    attachment: Attachment
    num_layers: int
    span_dir: tuple[float, float, float]    # world axes at rest, not necessarily unit
    chord_dir: tuple[float, float, float]   # leading → trailing edge, before orthogonalising
    span_bl: float              # base-to-tip distance (or axis-to-tip when from_axis)
    span_from_axis: bool        # span_bl measured from the body axis instead of the base
    le_sweep_bl: float          # leading-edge setback at the tip, along the chord
    le_power: float
    tip_chord_bl: float
    te_power: float
    thickness_bl: float         # maximum thickness at the base
    tip_thickness_ratio: float


DORSAL_FIN = FinSpec(
    name="dorsal_fin",
    attachment=Attachment(pair_side_idx=0, t_start=0.425, t_end=0.55, half_gap_deg=3.8),
    num_layers=10, span_dir=(0.0, 0.0, 1.0), chord_dir=(-1.0, 0.0, 0.0),
    span_bl=0.10, span_from_axis=False, le_sweep_bl=0.13, le_power=1.6, tip_chord_bl=0.02,
    te_power=3.0, thickness_bl=0.012, tip_thickness_ratio=0.15,
)
FLIPPER = FinSpec(
    name="flipper",
    attachment=Attachment(pair_side_idx=FLIPPER_PAIR, t_start=0.225, t_end=0.2875,
                          half_gap_deg=5.0),
    num_layers=8, span_dir=(-0.55, 0.75, -0.40), chord_dir=(-1.0, 0.0, -0.15),
    span_bl=0.16, span_from_axis=False, le_sweep_bl=0.045, le_power=1.2, tip_chord_bl=0.015,
    te_power=1.0, thickness_bl=0.012, tip_thickness_ratio=0.25,
)
FLUKE = FinSpec(
    name="fluke",
    attachment=Attachment(pair_side_idx=LATERAL_PAIR, t_start=0.875, t_end=0.997,
                          half_gap_deg=12.0),
    num_layers=10, span_dir=(0.0, 1.0, 0.0), chord_dir=(-1.0, 0.0, 0.0),
    span_bl=0.12, span_from_axis=True, le_sweep_bl=0.12, le_power=1.3, tip_chord_bl=0.03,
    te_power=1.5, thickness_bl=0.02, tip_thickness_ratio=0.15,
)


@dataclass(frozen=True)
class FinFrame:
    """Orthonormal fin axes in world coordinates at rest."""

    span: np.ndarray    # (3,) unit
    chord: np.ndarray   # (3,) unit, orthogonal to span
    normal: np.ndarray  # (3,) unit, chord × span

    def as_matrix(self) -> np.ndarray:
        """(3, 3) columns = part-local x (span), y (chord), z (normal)."""
        return np.stack([self.span, self.chord, self.normal], axis=1)


def fin_frame(spec: FinSpec, mirror: bool) -> FinFrame:
    """Axes of the fin; ``mirror`` reflects them to the animal's right (y → −y)."""
    flip = np.array([1.0, -1.0, 1.0]) if mirror else np.ones(3)
    span = np.asarray(spec.span_dir) * flip
    span = span / np.linalg.norm(span)
    chord = np.asarray(spec.chord_dir) * flip
    chord = chord - (chord @ span) * span
    chord = chord / np.linalg.norm(chord)
    return FinFrame(span=span, chord=chord, normal=np.cross(chord, span))


def airfoil(s: np.ndarray) -> np.ndarray:
    """Relative thickness along the chord (s = 0 leading, 1 trailing edge); never zero."""
    return 0.3 + 0.7 * np.sqrt(np.clip(4.0 * s * (1.0 - s), 0.0, 1.0))


def layer_positions(spec: FinSpec, frame: FinFrame, base_a: np.ndarray, base_b: np.ndarray,
                    length_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Loops of the fin above its base.

    base_a, base_b: (C, 3) base vertices of sides A and B, leading edge first.
    Returns (K, C, 3) positions of sides A and B for layers 1..K.
    """
    mid = 0.5 * (base_a + base_b)
    chord_pos = (mid - mid[0]) @ frame.chord
    base_chord = chord_pos[-1]
    s = chord_pos / base_chord
    straight = mid[0] + chord_pos[:, None] * frame.chord
    residual = mid - straight

    side_sign = np.sign((base_a - mid) @ frame.normal)
    base_half = 0.5 * spec.thickness_bl * length_m * airfoil(s)
    residual_a = base_a - mid - side_sign[:, None] * base_half[:, None] * frame.normal
    residual_b = base_b - mid + side_sign[:, None] * base_half[:, None] * frame.normal

    span_len = spec.span_bl * length_m
    if spec.span_from_axis:
        span_len -= float(mid[0] @ frame.span)  # loops are laid out from the base's leading edge

    f = np.arange(1, spec.num_layers + 1, dtype=np.float64)[:, None] / spec.num_layers
    fade = (1.0 - f) ** 2
    le = spec.le_sweep_bl * length_m * f ** spec.le_power
    tip_te = (spec.le_sweep_bl + spec.tip_chord_bl) * length_m
    te = base_chord + (tip_te - base_chord) * f ** spec.te_power
    along = le + s[None, :] * (te - le)
    centre = (mid[0] + along[..., None] * frame.chord + (f * span_len)[..., None] * frame.span
              + fade[..., None] * residual)
    half = base_half[None, :] * (1.0 - (1.0 - spec.tip_thickness_ratio) * f)
    offset = (side_sign[None, :] * half)[..., None] * frame.normal
    side_a = centre + offset + fade[..., None] * residual_a
    side_b = centre - offset + fade[..., None] * residual_b
    return side_a, side_b


def strip_faces(loops_a: np.ndarray, loops_b: np.ndarray) -> np.ndarray:
    """(F, 3) triangles of the walls and cap of an extruded strip.

    loops_a, loops_b: (K + 1, C) vertex indices of sides A and B, base loop first. The base
    strip's quads were wound A(r) → B(r) → B(r+1) → A(r+1) (outward), so each boundary edge
    p → q of the strip gets the wall p(k−1) → q(k−1) → q(k) → p(k), and the cap keeps the
    strip's own winding at the top loop.
    """
    num_chord = loops_a.shape[1]
    faces = []
    for k in range(1, loops_a.shape[0]):
        lower_a, lower_b, upper_a, upper_b = loops_a[k - 1], loops_b[k - 1], loops_a[k], loops_b[k]
        edges = [(lower_a[0], lower_b[0], upper_a[0], upper_b[0]),
                 (lower_b[-1], lower_a[-1], upper_b[-1], upper_a[-1])]
        for r in range(num_chord - 1):
            edges.append((lower_b[r], lower_b[r + 1], upper_b[r], upper_b[r + 1]))
            edges.append((lower_a[r + 1], lower_a[r], upper_a[r + 1], upper_a[r]))
        for p0, q0, p1, q1 in edges:
            faces.extend([(p0, q0, q1), (p0, q1, p1)])
    top_a, top_b = loops_a[-1], loops_b[-1]
    for r in range(num_chord - 1):
        faces.extend([(top_a[r], top_b[r], top_b[r + 1]), (top_a[r], top_b[r + 1], top_a[r + 1])])
    return np.asarray(faces, dtype=np.int64)
