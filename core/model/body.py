"""The body tube of the template: rings of vertices around the body axis, closed by two apexes.

Ring vertex ``j`` of ring ``i`` sits at angle φ_j(t_i) around the body axis, measured from
the dorsal midline (φ = 0) towards the animal's left (+y), so y = a·sin φ and z = c + b·cos φ with
a, b the half width and half height and c the lift of the section centre (the melon). Fins grow out of one-quad-wide strips of this grid (see
``fins.py``): each attachment is a pair of adjacent ring vertices whose angular gap widens
over the fin's base rows, so no ring vertex is swallowed by a fin and every station ring stays
on the body outline (fins excluded, morphometrics.md §4).
"""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.model.profile import centre_lift_fraction, height_fraction, width_fraction

# Angular layout of one side (0 < φ ≤ 180°): anchors with the number of evenly spaced fill
# vertices inserted after each. The other side mirrors it (φ → 360° − φ).
DORSAL_GAP_DEG = 2.0         # half gap of the dorsal pair away from the dorsal fin
LATERAL_GAP_DEG = 2.0        # half gap of the lateral pair away from the flukes
FLIPPER_CENTRE_DEG = 125.0   # flipper insertion below the lateral midline
FLIPPER_GAP_DEG = 5.0
FILLS_DORSAL_TO_LATERAL = 7
FILLS_LATERAL_TO_FLIPPER = 2
FILLS_FLIPPER_TO_VENTRAL = 4


@dataclass(frozen=True)
class Attachment:
    """Where a fin grows out of the body: the angular pair and the rows it spans."""

    pair_side_idx: int      # index of the pair's first vertex in the one-side layout
    t_start: float          # first base row (fraction of BL)
    t_end: float            # last base row (fraction of BL)
    half_gap_deg: float     # half gap of the pair over the base rows


# Positions in the one-side layout (0: dorsal pair vertex, 18: ventral midline).
DORSAL_PAIR = 0
LATERAL_PAIR = 1 + FILLS_DORSAL_TO_LATERAL
FLIPPER_PAIR = LATERAL_PAIR + 2 + FILLS_LATERAL_TO_FLIPPER
VENTRAL = FLIPPER_PAIR + 2 + FILLS_FLIPPER_TO_VENTRAL
RING_SIZE = 2 * VENTRAL + 1


def side_angles_deg(dorsal_gap: float, lateral_gap: float) -> np.ndarray:
    """(VENTRAL + 1,) angles of one side, dorsal pair vertex first, ventral midline last."""
    anchors = [
        (dorsal_gap, FILLS_DORSAL_TO_LATERAL),
        (90.0 - lateral_gap, 0),
        (90.0 + lateral_gap, FILLS_LATERAL_TO_FLIPPER),
        (FLIPPER_CENTRE_DEG - FLIPPER_GAP_DEG, 0),
        (FLIPPER_CENTRE_DEG + FLIPPER_GAP_DEG, FILLS_FLIPPER_TO_VENTRAL),
        (180.0, 0),
    ]
    angles = []
    for (start, fills), (stop, _) in zip(anchors[:-1], anchors[1:]):
        angles.extend(np.linspace(start, stop, fills + 2)[:-1])
    angles.append(180.0)
    return np.asarray(angles)


def ring_angles_deg(rows_t: np.ndarray, dorsal: Attachment, fluke: Attachment) -> np.ndarray:
    """(NR, RING_SIZE) angle of every ring vertex; j increases from the dorsal pair via +y."""
    rings = []
    for t in rows_t:
        dorsal_gap = dorsal.half_gap_deg if dorsal.t_start <= t <= dorsal.t_end else DORSAL_GAP_DEG
        lateral_gap = fluke.half_gap_deg if fluke.t_start <= t <= fluke.t_end else LATERAL_GAP_DEG
        side = side_angles_deg(dorsal_gap, lateral_gap)
        rings.append(np.concatenate([side, 360.0 - side[-2::-1]]))
    return np.asarray(rings)


def mirrored_quad(side_idx: int) -> int:
    """Ring quad index on the −y side mirroring the +y quad starting at ``side_idx``."""
    return RING_SIZE - 2 - side_idx


@dataclass(frozen=True)
class BodyTube:
    """Vertices and quads of the body: rostrum apex, rings, notch apex."""

    verts: np.ndarray        # (1 + NR·R + 1, 3) float64, metres
    rows_t: np.ndarray       # (NR,) ring positions, fractions of BL
    angles_deg: np.ndarray   # (NR, R) ring vertex angles
    rostrum_idx: int
    notch_idx: int

    def ring_vertex(self, row: int | np.ndarray, j: int | np.ndarray) -> np.ndarray:
        """Vertex index of ring ``row``, angle slot ``j`` (wrapping around the ring)."""
        return 1 + np.asarray(row) * RING_SIZE + np.mod(j, RING_SIZE)


def build_body(rows_t: np.ndarray, angles_deg: np.ndarray, length_m: float,
               root_t: float) -> BodyTube:
    """Place the body rings; x = (root_t − t)·BL so the root joint sits at the origin."""
    half_w = 0.5 * width_fraction(rows_t)[:, None] * length_m
    half_h = 0.5 * height_fraction(rows_t)[:, None] * length_m
    lift = centre_lift_fraction(rows_t)[:, None] * length_m
    phi = np.deg2rad(angles_deg)
    x = np.broadcast_to(((root_t - rows_t) * length_m)[:, None], phi.shape)
    ring_xyz = np.stack([x, half_w * np.sin(phi), lift + half_h * np.cos(phi)], axis=-1)
    rostrum = np.array([[root_t * length_m, 0.0, 0.0]])
    notch = np.array([[(root_t - 1.0) * length_m, 0.0, 0.0]])
    verts = np.concatenate([rostrum, ring_xyz.reshape(-1, 3), notch])
    return BodyTube(verts=verts, rows_t=rows_t, angles_deg=angles_deg,
                    rostrum_idx=0, notch_idx=len(verts) - 1)


def body_faces(tube: BodyTube,
               removed_quads: set[tuple[int, int]]) -> tuple[np.ndarray, np.ndarray]:
    """Outward-wound triangles of the tube, leaving out the quads (row, j) given.

    Returns (F, 3) int64 faces and (F,) int64 ring slot ``j`` of the quad (or apex fan
    triangle) each face belongs to, which places it on the texture atlas.
    """
    num_rows = len(tube.rows_t)
    faces, slots = [], []
    for j in range(RING_SIZE):
        a, b = tube.ring_vertex(0, j), tube.ring_vertex(0, j + 1)
        faces.append((tube.rostrum_idx, b, a))
        slots.append(j)
    for i in range(num_rows - 1):
        for j in range(RING_SIZE):
            if (i, j) not in removed_quads:
                faces.extend(quad_triangles(*quad_corners(tube, i, j)))
                slots.extend([j, j])
    last = num_rows - 1
    for j in range(RING_SIZE):
        a, b = tube.ring_vertex(last, j), tube.ring_vertex(last, j + 1)
        faces.append((tube.notch_idx, a, b))
        slots.append(j)
    return np.asarray(faces, dtype=np.int64), np.asarray(slots, dtype=np.int64)


def quad_corners(tube: BodyTube, row: int, j: int) -> tuple[int, int, int, int]:
    """Corners of quad (row, j) in outward cyclic order."""
    return (int(tube.ring_vertex(row, j)), int(tube.ring_vertex(row, j + 1)),
            int(tube.ring_vertex(row + 1, j + 1)), int(tube.ring_vertex(row + 1, j)))


def quad_triangles(p: int, q: int, r: int, s: int) -> list[tuple[int, int, int]]:
    """Two triangles of the cyclic quad p→q→r→s, same winding."""
    return [(p, q, r), (p, r, s)]
