"""UV atlas and the default grayscale albedo of the template.

Texture coordinates (u, v) ∈ [0, 1]²: u runs along the image columns (0 = left edge), v along
the rows (0 = top edge). The atlas holds the body, unrolled with the seam on the ventral
midline (rostrum left, notch right; left flank in the lower half, right flank in the upper
half, the dorsal midline across the middle), and below it one cell per fin type with the fin's
dorsal (or left) face in the cell's upper half and the other face in its lower half.

The albedo carries the countershading of bottlenose dolphins: a dark dorsal cape, grey flanks
and a light belly; fins dark, the flukes lighter underneath.
"""

from dataclasses import dataclass, field

import numpy as np

from dolphinfit.core.model.skeleton import smoothstep

ALBEDO_SIZE = 512  # texels per side (the paper's grayscale albedo; DESIGN.md §4)

BODY_U = (0.01, 0.99)
BODY_V = (0.01, 0.69)
FIN_V = (0.72, 0.99)
FIN_SPLIT_V = 0.855          # upper face above, lower face below
FIN_CELLS_U = {"dorsal_fin": (0.01, 0.32), "flipper": (0.345, 0.655), "fluke": (0.68, 0.99)}

TRANSITION_DEG = 14.0


@dataclass(frozen=True)
class Countershading:
    """Luminances of the colour pattern (0 black, 1 white); the default is the template's."""

    cape: float = 0.24
    flank: float = 0.50
    belly: float = 0.86
    fins: dict[str, tuple[float, float]] = field(default_factory=lambda: {
        "dorsal_fin": (0.22, 0.22), "flipper": (0.30, 0.42), "fluke": (0.26, 0.58)})
    cape_edge_shift_deg: float = 0.0     # negative: a narrower cape
    cape_fade_t: float | None = None     # the cape fades into the flank grey behind this fraction


TEMPLATE_SHADING = Countershading()


def body_uv(t: np.ndarray, phi_deg: np.ndarray) -> np.ndarray:
    """(..., 2) UVs of body points at fraction ``t`` and signed angle φ ∈ [−180°, 180°]."""
    u = BODY_U[0] + np.asarray(t) * (BODY_U[1] - BODY_U[0])
    v = BODY_V[0] + (np.asarray(phi_deg) + 180.0) / 360.0 * (BODY_V[1] - BODY_V[0])
    return np.stack(np.broadcast_arrays(u, v), axis=-1)


def fin_uv(fin: str, chord_s: np.ndarray, span_f: np.ndarray, upper: bool) -> np.ndarray:
    """(..., 2) UVs of fin points at chord fraction ``chord_s`` and span fraction ``span_f``.

    ``upper`` picks the cell's upper half (the fin's dorsal or left face).
    """
    u0, u1 = FIN_CELLS_U[fin]
    u = u0 + np.asarray(chord_s) * (u1 - u0)
    f = np.asarray(span_f)
    if upper:
        v = FIN_V[0] + f * (FIN_SPLIT_V - 0.005 - FIN_V[0])
    else:
        v = FIN_V[1] - f * (FIN_V[1] - FIN_SPLIT_V - 0.005)
    return np.stack(np.broadcast_arrays(u, v), axis=-1)


def cape_edge_deg(t: np.ndarray) -> np.ndarray:
    """Angle from the dorsal midline where the dark cape ends, along the body."""
    return 62.0 + 16.0 * np.cos(2.0 * np.pi * (t - 0.42))


def body_luma(t: np.ndarray, phi_deg: np.ndarray,
              shading: Countershading = TEMPLATE_SHADING) -> np.ndarray:
    """Countershading luminance at body fraction ``t`` and angle φ (either sign)."""
    angle = np.abs(phi_deg)
    edge = cape_edge_deg(t) + shading.cape_edge_shift_deg
    to_flank = smoothstep((angle - edge) / TRANSITION_DEG)
    if shading.cape_fade_t is not None:
        fade = smoothstep((t - shading.cape_fade_t) / 0.15)
        to_flank = to_flank + (1.0 - to_flank) * fade
    to_belly = smoothstep((angle - 135.0) / TRANSITION_DEG)
    return (shading.cape + (shading.flank - shading.cape) * to_flank
            + (shading.belly - shading.flank) * to_belly)


def build_albedo(size: int = ALBEDO_SIZE,
                 shading: Countershading = TEMPLATE_SHADING) -> np.ndarray:
    """(size, size) uint8 grayscale albedo laid out as the atlas above.

    Every texel belongs to a region, the margins continuing their region's pattern, so
    bilinear sampling at a region's edge never blends in a foreign colour.
    """
    centres = (np.arange(size) + 0.5) / size
    v, u = np.meshgrid(centres, centres, indexing="ij")
    in_body = v < 0.5 * (BODY_V[1] + FIN_V[0])
    t = np.clip((u - BODY_U[0]) / (BODY_U[1] - BODY_U[0]), 0.0, 1.0)
    phi = np.clip((v - BODY_V[0]) / (BODY_V[1] - BODY_V[0]), 0.0, 1.0) * 360.0 - 180.0
    luma = np.where(in_body, body_luma(t, phi, shading), 0.0)

    cells = list(FIN_CELLS_U.items())
    for k, (fin, (u0, u1)) in enumerate(cells):
        left = 0.0 if k == 0 else 0.5 * (cells[k - 1][1][1] + u0)
        right = 1.0 if k == len(cells) - 1 else 0.5 * (u1 + cells[k + 1][1][0])
        in_cell = ~in_body & (u >= left) & (u < right)
        luma_upper, luma_lower = shading.fins[fin]
        luma[in_cell] = np.where(v[in_cell] < FIN_SPLIT_V, luma_upper, luma_lower)
    return np.round(luma * 255.0).astype(np.uint8)
