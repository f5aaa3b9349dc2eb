"""A suggested length midline and widths from an animal's mask, for the user to review.

The midline is found as a person draws it, rostrum tip to fluke notch along the middle of the
body:

1. **A first guess**: the mask's principal axis, cut into ``SLICES`` cross-sections between
   its extreme pixels.
2. **Re-centred** ``ROUNDS`` times: each point moves to the middle of the mask's cross-section
   perpendicular to the current midline (not to the first axis, so a bent body keeps its
   midline inside it), and the points are smoothed along the body. A point whose
   cross-section does not start inside the mask (beside a bent tail, or between the fluke
   lobes behind the notch) keeps its place.
3. **The ends**: towards the head, from the middle of the body along the midline (straight
   on where it ends inside the mask) to where it leaves the mask, and there the mask's point
   furthest forward along the head's direction: the rostrum tip. Towards the tail, along the
   midline to the peduncle (its narrowest cross-section), then straight on in the tail
   stock's direction to where that line leaves the mask: the fluke notch, where the body's
   line meets the trailing edge between the lobes, not the fluke tips behind it.

The ends are told apart by the tail stock: 10–30 % of the body from the tail the peduncle
narrows to a fifth or less of the body's greatest width, while the same share from the
rostrum the head has broadened to half of it or more, with or without the flukes showing.
Measured by ``dolphinfit bench real`` on real whale outlines with hand points and images.

Widths are the body's, not its fins' (``suggested_edges``). Each side's outline is sampled as
its offset from the midline every ``PROFILE_STEP`` of the length between the stations:

- **Flippers and a dorsal fin** seen beside the body stand out of that profile as a bump no
  longer than their base. In ``FIN_ZONE``, a stretch of the profile above its opening (the
  sliding minimum's sliding maximum over ``FIN_BASE``), which somewhere stands ``FIN_HEIGHT``
  or more above it, is a fin; the body's outline runs straight across it, between the
  profile either side. An opening of the mask with a disc (the earlier way) left a flipper's
  root and fillets, wider than any disc that keeps the body's shape, and a flipper lying
  along the body, which makes it wider rather than longer.
- **Fluke lobes** begin ahead of the notch, so the rear stations' perpendiculars run out along
  them. Behind the narrowest point of the tail stock (from ``FLUKE_ZONE``), where the lobes then
  reach ``FLUKE_JUMP`` × its offset, the tail stock is taken to taper straight to the notch.
"""

import numpy as np
from scipy.ndimage import (
    map_coordinates, maximum_filter1d, minimum_filter1d, uniform_filter1d,
)

from dolphinfit.core.measure.annotation import (
    MASK_LEVEL, MASK_STEP_PX, Annotation, Stations, edge_offsets, place_stations, suggest_edges,
)
from dolphinfit.core.measure.stations import STATION_FRACTIONS

WAIST_ZONE = (0.1, 0.3)   # shares of the body from an end where the tail stock is narrowest
SLICES = 41           # midline points while it is found
ROUNDS = 3            # re-centrings
SMOOTHING = 5         # points averaged along the body after each re-centring
SUGGESTED_POINTS = 7  # clicks of the suggested midline, ends included
STOCK_POINTS = 4      # the tail stock's direction: over this many midline points (~10 %)
FLUKE_JUMP = 1.8      # widths this many × the peduncle's: the flukes
HEAD_AXIS = (0.03, 0.15)     # the head's direction: the midline between these shares
FIN_ZONE = (0.15, 0.65)   # stations measured under flippers and a dorsal fin (share of length)
FIN_BASE = 0.12           # the longest fin base along the body taken out there, × length
FIN_HEIGHT = 0.006        # a fin stands at least this far out of the body's outline, × length
FLUKE_ZONE = 0.75         # from here on the tail stock is looked for ahead of the fluke lobes
PROFILE_STEP = 0.01       # each side's outline is sampled this often between stations, × length


def midline_from_mask(mask: np.ndarray, num_points: int = SUGGESTED_POINTS,
                      head_near: np.ndarray | None = None) -> np.ndarray:
    """(num_points, 2) midline (u, v) from the rostrum tip to the fluke notch of ``mask``, at
    equal arc length. ``head_near``: a point (u, v) nearer the head than the tail, where it is
    known (else the narrower end is taken for the head).

    mask: (H, W) bool, True = animal (or a coverage in 0…1, its outline at 0.5). Raises
    ValueError when the mask is (nearly) empty.
    """
    coverage = np.asarray(mask, dtype=np.float64)
    v, u = np.nonzero(coverage >= MASK_LEVEL)
    if u.size < 20:
        raise ValueError("the mask holds no animal")
    points = first_guess(np.stack([u, v], axis=1).astype(np.float64))
    for _ in range(ROUNDS):
        points = recentred(coverage, points)
    if head_near is not None:
        if np.linalg.norm(points[-1] - head_near) < np.linalg.norm(points[0] - head_near):
            points = points[::-1]
    elif _waist(coverage, points) < _waist(coverage, points[::-1]):
        points = points[::-1]   # the narrow tail stock is at the other end
    middle = len(points) // 2
    midline = np.concatenate([_walk(coverage, points[middle::-1])[::-1],
                              to_notch(coverage, points[middle:])[1:]])
    midline[0] = head_tip(coverage >= MASK_LEVEL, midline)
    return resampled(midline, num_points)


def first_guess(points: np.ndarray) -> np.ndarray:
    """(SLICES, 2) points along the principal axis of pixels (N, 2), extreme to extreme, each
    in the middle of its cross-section."""
    centre = points.mean(axis=0)
    _, _, axes = np.linalg.svd(points - centre, full_matrices=False)
    axis, normal = axes[0], np.array([-axes[0][1], axes[0][0]])
    along, across = (points - centre) @ axis, (points - centre) @ normal
    edges = np.linspace(along.min(), along.max(), SLICES + 1)
    slot = np.clip(np.searchsorted(edges, along, side="right") - 1, 0, SLICES - 1)
    low = np.full(SLICES, np.inf)
    high = np.full(SLICES, -np.inf)
    np.minimum.at(low, slot, across)
    np.maximum.at(high, slot, across)
    middle = np.where(np.isfinite(low), (low + high) / 2, 0.0)
    at = (edges[:-1] + edges[1:]) / 2
    return centre + at[:, None] * axis + middle[:, None] * normal


def recentred(coverage: np.ndarray, points: np.ndarray) -> np.ndarray:
    """``points`` moved to the middle of the mask's cross-sections perpendicular to the
    polyline through them, then smoothed along it; the end points stay."""
    stations = polyline_stations(points)
    edges = suggest_edges(coverage, stations)
    middles = edges.mean(axis=1)
    found = np.all(np.isfinite(middles), axis=1)
    moved = np.where(found[:, None], middles, points)
    smooth = uniform_filter1d(moved, SMOOTHING, axis=0, mode="nearest")
    smooth[[0, -1]] = moved[[0, -1]]
    return smooth


def polyline_stations(points: np.ndarray, reach_px: float | None = None) -> Stations:
    """Stations at each point of a polyline (N, 2), their normals perpendicular to the chord
    between its neighbours (central differences). Edges are looked for up to half of
    ``reach_px`` from them (default: the polyline's length)."""
    tangents = np.gradient(points, axis=0)
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-12)
    length = (float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))
              if reach_px is None else float(reach_px))
    return Stations(length_px=length, fractions=np.linspace(0.0, 1.0, len(points)),
                    points_px=points, normals=np.stack([-tangents[:, 1], tangents[:, 0]], 1))


def peduncle_index(widths: np.ndarray) -> int | None:
    """The index of the peduncle in a tail half's widths (from the middle of the body): the
    narrowest cross-section before the widths first jump to ``FLUKE_JUMP`` × the narrowest so
    far (the flukes' span), at least ``STOCK_POINTS`` in; None without a width."""
    narrowest = None
    for index in range(STOCK_POINTS, len(widths)):
        width = widths[index]
        if not np.isfinite(width):
            continue
        if narrowest is not None and width > FLUKE_JUMP * widths[narrowest]:
            break
        if narrowest is None or width < widths[narrowest]:
            narrowest = index
    return narrowest


def to_notch(coverage: np.ndarray, tail: np.ndarray) -> np.ndarray:
    """The tail half of the midline (from the middle of the body) to the fluke notch: along
    it to the peduncle (its narrowest cross-section), then straight on in the tail stock's
    direction to where that line leaves the mask (module doc, 3). Between the fluke lobes
    the cross-sections' middles follow the larger lobe, not the line of the body."""
    reach = float(np.sum(np.linalg.norm(np.diff(tail, axis=0), axis=1)))
    edges = suggest_edges(coverage, polyline_stations(tail, reach_px=2 * reach))
    widths = np.linalg.norm(edges[:, 0] - edges[:, 1], axis=1)
    peduncle = peduncle_index(widths)
    if peduncle is None:
        return _walk(coverage, tail)
    direction = tail[peduncle] - tail[peduncle - STOCK_POINTS]
    return _walk(coverage, np.concatenate([tail[:peduncle + 1],
                                           tail[peduncle:peduncle + 1] + direction]))


def head_tip(mask: np.ndarray, midline: np.ndarray) -> np.ndarray:
    """(2,) the rostrum tip: the mask's point furthest forward along the head's direction
    (the midline from ``HEAD_AXIS[1]`` to ``HEAD_AXIS[0]`` of its length), in the middle of
    the pixels within a pixel of the front, half a pixel beyond their centres."""
    vertices = arc_lengths(midline)
    ends = at_arc(midline, vertices, np.asarray(HEAD_AXIS) * vertices[-1])
    forward = (ends[0] - ends[1]) / max(np.linalg.norm(ends[0] - ends[1]), 1e-12)
    v, u = np.nonzero(mask)
    pixels = np.stack([u, v], axis=1).astype(np.float64)
    along = (pixels - ends[1]) @ forward
    front = pixels[along >= along.max() - 1.0]
    across = forward[::-1] * np.array([-1.0, 1.0])
    lateral = float(np.mean((front - ends[1]) @ across))
    return ends[1] + (along.max() + 0.5) * forward + lateral * across


def _walk(coverage: np.ndarray, points: np.ndarray) -> np.ndarray:
    """``points`` (from inside the mask outwards, the last direction carried on to the
    image's edge) up to where the path first leaves the mask."""
    height, width = coverage.shape
    direction = points[-1] - points[-2]
    direction /= max(np.linalg.norm(direction), 1e-12)
    reach = float(np.hypot(height, width))
    path = np.concatenate([points, points[-1] + reach * direction[None, :]])
    dense, arc = _densified(path)
    values = map_coordinates(coverage, [dense[:, 1], dense[:, 0]], order=1, mode="constant",
                             cval=0.0)
    outside = values < MASK_LEVEL
    if not outside.any():
        return points
    exit_idx = max(int(np.argmax(outside)), 1)
    inner, outer = values[exit_idx - 1], values[exit_idx]
    share = (inner - MASK_LEVEL) / (inner - outer) if inner != outer else 0.0
    at = arc[exit_idx - 1] + share * (arc[exit_idx] - arc[exit_idx - 1])
    vertices = arc_lengths(path)
    kept = path[vertices < at]
    return np.concatenate([kept, at_arc(path, vertices, np.array([at]))])


def _densified(path: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points every ``MASK_STEP_PX`` along a polyline and their arc lengths."""
    vertices = arc_lengths(path)
    arc = np.arange(0.0, vertices[-1], MASK_STEP_PX)
    return (at_arc(path, vertices, arc), arc)


def _waist(coverage: np.ndarray, points: np.ndarray) -> float:
    """The narrowest cross-section between ``WAIST_ZONE`` of the body from the first point:
    the tail stock when it starts at the tail, the broadening head when it starts there."""
    vertices = arc_lengths(points)
    near = np.linspace(*WAIST_ZONE, 9) * vertices[-1]
    zone = at_arc(points, vertices, near)
    edges = suggest_edges(coverage, polyline_stations(zone, reach_px=vertices[-1]))
    widths = np.linalg.norm(edges[:, 0] - edges[:, 1], axis=1)
    return float(np.nanmin(widths)) if np.isfinite(widths).any() else 0.0


def arc_lengths(points: np.ndarray) -> np.ndarray:
    """(N,) arc length (px) at each point of a polyline (N, 2), 0 at the first."""
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])


def at_arc(points: np.ndarray, arc: np.ndarray, at: np.ndarray) -> np.ndarray:
    """(M, 2) points of a polyline (N, 2) with arc lengths ``arc`` at arc lengths ``at``."""
    return np.stack([np.interp(at, arc, points[:, 0]), np.interp(at, arc, points[:, 1])], 1)


def resampled(midline: np.ndarray, num_points: int) -> np.ndarray:
    """(num_points, 2) points at equal arc length along a polyline, ends included."""
    vertices = arc_lengths(midline)
    at = np.linspace(0.0, vertices[-1], num_points)
    return at_arc(midline, vertices, at)


def suggested_edges(mask: np.ndarray, stations: Stations) -> np.ndarray:
    """(S, 2, 2) edge points of ``suggest_edges``, the body's where fins join it: each side
    moved in to its outline with the fins taken out (module doc)."""
    edges = suggest_edges(mask, stations)
    if len(stations.fractions) < 2:
        return edges
    dense, at = subdivided(stations)
    offsets = edge_offsets(dense, suggest_edges(mask, dense))
    for side_idx, sign in enumerate((1.0, -1.0)):
        body = body_offsets(dense.fractions, sign * offsets[:, side_idx], stations.length_px)[at]
        inside = body < sign * offsets[at, side_idx]   # False where NaN
        edges[inside, side_idx] = (stations.points_px[inside]
                                   + sign * body[inside, None] * stations.normals[inside])
    return edges


def subdivided(stations: Stations) -> tuple[Stations, np.ndarray]:
    """Stations every ``PROFILE_STEP`` (or less) between those given, their points and normals
    interpolated along straight lines between them, and the indices of the given ones."""
    gaps = np.round(np.diff(stations.fractions) / PROFILE_STEP, 6)   # 0.05 / 0.01 > 5 in floats
    parts = np.maximum(np.ceil(gaps), 1).astype(int)
    at = np.concatenate([[0], np.cumsum(parts)])
    share = np.concatenate([np.arange(n) / n + k for k, n in enumerate(parts)] + [[len(parts)]])
    knots = np.arange(len(stations.fractions))

    def along(values: np.ndarray) -> np.ndarray:
        return np.stack([np.interp(share, knots, column) for column in values.T], axis=1)

    normals = along(stations.normals)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return Stations(length_px=stations.length_px,
                    fractions=np.interp(share, knots, stations.fractions),
                    points_px=along(stations.points_px), normals=normals), at


def body_offsets(fractions: np.ndarray, offsets: np.ndarray, length_px: float) -> np.ndarray:
    """(N,) one side's outline offsets from the midline (N,) at ``fractions`` (spaced about
    ``PROFILE_STEP``) with flippers, dorsal fin and fluke lobes taken out (module doc); NaN
    stays NaN."""
    width = 2 * int(round(FIN_BASE / PROFILE_STEP / 2)) + 1   # odd: the same window both ways
    eroded = minimum_filter1d(np.where(np.isnan(offsets), np.inf, offsets), width,
                              mode="nearest")
    opened = maximum_filter1d(eroded, width, mode="nearest")
    zone = (fractions >= FIN_ZONE[0]) & (fractions <= FIN_ZONE[1])
    above = zone & (offsets > opened)   # False at NaN
    stretch = np.cumsum(~above)         # one label per stretch of the outline above the opening
    standing_out = above & (offsets - opened > FIN_HEIGHT * length_px)
    fins = above & np.isin(stretch, stretch[standing_out])
    body = offsets.copy()
    if fins.any():   # straight across each fin, between the outline either side of it
        known = ~fins & np.isfinite(offsets)
        body[fins] = np.interp(fractions[fins], fractions[known], offsets[known])
    return without_flukes(fractions, body)


def without_flukes(fractions: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """One side's offsets (N,) with the tail stock tapering straight from its narrowest point
    in ``FLUKE_ZONE`` to nothing at the notch, where the fluke lobes (``FLUKE_JUMP`` × that
    offset) show behind that point (module doc)."""
    rear = np.flatnonzero((fractions >= FLUKE_ZONE) & np.isfinite(offsets))
    if rear.size == 0:
        return offsets
    narrowest = rear[np.argmin(offsets[rear])]
    behind = slice(narrowest + 1, None)
    if not np.any(offsets[behind] >= FLUKE_JUMP * offsets[narrowest]):
        return offsets
    taper = offsets[narrowest] * (1 - fractions[behind]) / (1 - fractions[narrowest])
    body = offsets.copy()
    body[behind] = np.minimum(offsets[behind], taper)
    return body


def annotation_from_mask(mask: np.ndarray, frame_idx: int = 0) -> Annotation:
    """The length midline and the 19 widths that a mask suggests, as "suggest edges" places
    them in the app; nobody has reviewed them."""
    midline = midline_from_mask(mask)
    return Annotation(frame_idx=frame_idx, midline_px=midline,
                      edges_px=suggested_edges(mask, place_stations(midline,
                                                                    STATION_FRACTIONS)))
