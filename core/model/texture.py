"""UV atlas and the default grayscale albedo of the template.

Texture coordinates (u, v) ∈ [0, 1]²: u runs along the image columns (0 = left edge), v along
the rows (0 = top edge). The atlas holds the body, unrolled with the seam on the ventral
midline (rostrum left, notch right; left flank in the lower half, right flank in the upper
half, the dorsal midline across the middle), and below it one cell per fin type with the fin's
dorsal (or left) face in the cell's upper half and the other face in its lower half.

The albedo carries the countershading of bottlenose dolphins: a dark dorsal cape, grey flanks
and a light belly; fins dark, the flukes lighter underneath.
"""

import numpy as np

from core.model.skeleton import smoothstep

ALBEDO_SIZE = 512  # texels per side (the paper's grayscale albedo; DESIGN.md §4)

BODY_U = (0.01, 0.99)
BODY_V = (0.01, 0.69)
FIN_V = (0.72, 0.99)
FIN_SPLIT_V = 0.855          # upper face above, lower face below
FIN_CELLS_U = {"dorsal_fin": (0.01, 0.32), "flipper": (0.345, 0.655), "fluke": (0.68, 0.99)}

# Luminance of the countershading (0 black, 1 white).
CAPE_LUMA = 0.24
FLANK_LUMA = 0.50
BELLY_LUMA = 0.86
TRANSITION_DEG = 14.0
FIN_LUMA = {"dorsal_fin": (0.22, 0.22), "flipper": (0.30, 0.42), "fluke": (0.26, 0.58)}


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


def body_luma(t: np.ndarray, phi_deg: np.ndarray) -> np.ndarray:
    """Countershading luminance at body fraction ``t`` and angle φ (either sign)."""
    angle = np.abs(phi_deg)
    to_flank = smoothstep((angle - cape_edge_deg(t)) / TRANSITION_DEG)
    to_belly = smoothstep((angle - 135.0) / TRANSITION_DEG)
    return CAPE_LUMA + (FLANK_LUMA - CAPE_LUMA) * to_flank + (BELLY_LUMA - FLANK_LUMA) * to_belly


def build_albedo(size: int = ALBEDO_SIZE) -> np.ndarray:
    """(size, size) uint8 grayscale albedo laid out as the atlas above.

    Every texel belongs to a region, the margins continuing their region's pattern, so
    bilinear sampling at a region's edge never blends in a foreign colour.
    """
    centres = (np.arange(size) + 0.5) / size
    v, u = np.meshgrid(centres, centres, indexing="ij")
    in_body = v < 0.5 * (BODY_V[1] + FIN_V[0])
    t = np.clip((u - BODY_U[0]) / (BODY_U[1] - BODY_U[0]), 0.0, 1.0)
    phi = np.clip((v - BODY_V[0]) / (BODY_V[1] - BODY_V[0]), 0.0, 1.0) * 360.0 - 180.0
    luma = np.where(in_body, body_luma(t, phi), 0.0)

    cells = list(FIN_CELLS_U.items())
    for k, (fin, (u0, u1)) in enumerate(cells):
        left = 0.0 if k == 0 else 0.5 * (cells[k - 1][1][1] + u0)
        right = 1.0 if k == len(cells) - 1 else 0.5 * (u1 + cells[k + 1][1][0])
        in_cell = ~in_body & (u >= left) & (u < right)
        luma_upper, luma_lower = FIN_LUMA[fin]
        luma[in_cell] = np.where(v[in_cell] < FIN_SPLIT_V, luma_upper, luma_lower)
    return np.round(luma * 255.0).astype(np.uint8)
