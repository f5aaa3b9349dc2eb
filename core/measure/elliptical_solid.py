"""The elliptical volume model (core/measure/elliptical.py) as a closed triangle mesh, to show.

Layout: centred on the origin, body axis along x with the rostrum towards +x (as the
template, DESIGN.md §4): the station at fraction p of body length BL lies at x = BL·(½ − p),
the rostrum apex at x = +BL/2 and the fluke-notch apex at x = −BL/2. Width along y, height
along z. Each station is a ring of ``ring_points`` vertices on the ellipse of axes w and h.

The mesh is watertight with outward winding. Its divergence-theorem volume is the 20-frustum
volume times the polygon/ellipse area ratio (n/2π)·sin(2π/n) of an n-point ring, exactly: the
quads between rings of different aspect ratio are twisted, but their twists cancel around a ring
(they add up to a sum of sin(2θ_j + δ) over the n ring angles, which is zero for n ≥ 3).
"""

import numpy as np

from dolphinfit.core.measure.stations import NUM_STATIONS, STATION_FRACTIONS

MIN_RING_POINTS = 3


def _ring_faces(num_rings: int, ring_points: int) -> np.ndarray:
    """(2·(num_rings − 1)·n, 3) triangles joining consecutive rings (vertex 1 + k·n + j)."""
    k, j = np.meshgrid(np.arange(num_rings - 1), np.arange(ring_points), indexing="ij")
    j_next = (j + 1) % ring_points
    a = 1 + k * ring_points + j          # ring k, towards the rostrum
    b = a + ring_points                  # ring k + 1
    c = 1 + (k + 1) * ring_points + j_next
    d = 1 + k * ring_points + j_next
    quads = np.stack([np.stack([a, b, c], -1), np.stack([a, c, d], -1)], axis=-2)
    return quads.reshape(-1, 3)


def _cap_faces(apex: int, ring_start: int, ring_points: int, towards_plus_x: bool) -> np.ndarray:
    """(n, 3) fan from an apex to a ring, wound outward."""
    j = np.arange(ring_points)
    here, after = ring_start + j, ring_start + (j + 1) % ring_points
    apexes = np.full(ring_points, apex)
    order = (apexes, here, after) if towards_plus_x else (apexes, after, here)
    return np.stack(order, axis=-1)


def elliptical_solid(length_m: float, widths_m: np.ndarray, heights_m: np.ndarray,
                     ring_points: int = 32) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (2 + S·n, 3) in metres and faces (2·S·n, 3) of the elliptical solid.

    length_m: body length BL; widths_m, heights_m: (S,) finite, non-negative station values
    (tail option already applied); ring_points: n vertices per ring, the first at
    y = +w/2, z = 0, then counter-clockwise about +x. Vertex 0 is the rostrum apex, the last
    the notch apex.
    """
    widths = np.asarray(widths_m, dtype=np.float64)
    heights = np.asarray(heights_m, dtype=np.float64)
    if widths.shape != (NUM_STATIONS,) or heights.shape != (NUM_STATIONS,):
        raise ValueError(f"widths and heights must have shape ({NUM_STATIONS},), got "
                         f"{widths.shape} and {heights.shape}")
    if not (np.isfinite(widths).all() and np.isfinite(heights).all()
            and (widths >= 0).all() and (heights >= 0).all()):
        raise ValueError("widths and heights must be finite and non-negative")
    if ring_points < MIN_RING_POINTS:
        raise ValueError(f"ring_points must be at least {MIN_RING_POINTS}, got {ring_points}")
    theta = 2.0 * np.pi * np.arange(ring_points) / ring_points
    x = np.broadcast_to(length_m * (0.5 - STATION_FRACTIONS)[:, None],
                        (NUM_STATIONS, ring_points))
    y = widths[:, None] / 2.0 * np.cos(theta)
    z = heights[:, None] / 2.0 * np.sin(theta)
    rings = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    notch = 1 + NUM_STATIONS * ring_points
    verts = np.concatenate([[[length_m / 2.0, 0.0, 0.0]], rings, [[-length_m / 2.0, 0.0, 0.0]]])
    faces = np.concatenate([
        _cap_faces(0, 1, ring_points, towards_plus_x=True),
        _ring_faces(NUM_STATIONS, ring_points),
        _cap_faces(notch, notch - ring_points, ring_points, towards_plus_x=False),
    ])
    return verts, faces.astype(np.int64)
