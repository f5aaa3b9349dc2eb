"""Edits of one measured frame, as pure functions: each returns a new Measurement.

The app turns each into an undoable command; the tests call them directly. Geometry is that of
core/measure/annotation.py: stations at equal arc length along the interpolating midline,
offsets along each station's unit normal (side A positive).
"""

from dataclasses import replace

import numpy as np

from dolphinfit.core.measure.annotation import SIDES, Stations, edge_offsets, place_stations
from dolphinfit.core.measure.edge_sources import EDGE_CLICKED, EDGE_SUGGESTED, moved_source
from dolphinfit.core.project.model import Measurement


def _with_midline(m: Measurement, midline: np.ndarray) -> Measurement:
    if len(midline) >= 2 and np.any(np.linalg.norm(np.diff(midline, axis=0), axis=1) == 0):
        raise ValueError("two consecutive midline points may not coincide")
    return replace(m, midline_px=midline)


def add_midline_point(m: Measurement, u: float, v: float) -> Measurement:
    """Append a click at the fluke-notch end of the midline."""
    return _with_midline(m, np.vstack([m.midline_px, [[u, v]]]))


def insert_midline_point(m: Measurement, index: int, u: float, v: float) -> Measurement:
    """Insert a click before midline point ``index`` (0 … N)."""
    if not 0 <= index <= len(m.midline_px):
        raise IndexError(f"midline point {index} out of range")
    return _with_midline(m, np.insert(m.midline_px, index, [u, v], axis=0))


def move_midline_point(m: Measurement, index: int, u: float, v: float) -> Measurement:
    """Move midline point ``index`` to (u, v)."""
    midline = m.midline_px.copy()
    midline[index] = (u, v)
    return _with_midline(m, midline)


def delete_midline_point(m: Measurement, index: int) -> Measurement:
    """Remove midline point ``index``."""
    return _with_midline(m, np.delete(m.midline_px, index, axis=0))


def nearest_segment(m: Measurement, u: float, v: float) -> int:
    """Index at which a click at (u, v) would be inserted: after the nearest midline segment's
    start. Needs at least two points."""
    pts = m.midline_px
    starts, ends = pts[:-1], pts[1:]
    seg = ends - starts
    t = np.clip(np.einsum("ij,ij->i", np.array([u, v]) - starts, seg)
                / np.einsum("ij,ij->i", seg, seg), 0.0, 1.0)
    closest = starts + t[:, None] * seg
    return int(np.argmin(np.linalg.norm(closest - [u, v], axis=1))) + 1


def reverse_midline(m: Measurement) -> Measurement:
    """Swap rostrum and notch ends, keeping every edge where it is on the image.

    Station k of the reversed midline is station S−1−k of the old one (the fractions are
    symmetric) and its normal points the other way, so side A becomes side B.
    """
    offsets = -m.offsets_px[::-1, ::-1]
    mirror = None if m.mirror_side is None else SIDES[1 - SIDES.index(m.mirror_side)]
    return replace(m, midline_px=m.midline_px[::-1], offsets_px=offsets,
                   skipped=m.skipped[::-1], mirror_side=mirror,
                   edge_sources=m.edge_sources[::-1, ::-1])


def stations_of(m: Measurement) -> Stations | None:
    """Station points and normals of the midline, None without a length."""
    return place_stations(m.midline_px) if m.has_length else None


def offset_of_point(stations: Stations, station: int, u: float, v: float) -> float:
    """Signed distance of (u, v) from ``station`` along its normal (the handle constraint)."""
    return float(np.dot(np.array([u, v]) - stations.points_px[station], stations.normals[station]))


def _with_edge(m: Measurement, station: int, side: int, offset_px: float,
               source: str) -> Measurement:
    offsets = m.offsets_px.copy()
    offsets[station, side] = offset_px
    sources = m.edge_sources.copy()
    sources[station, side] = source
    skipped = m.skipped.copy()
    if np.isfinite(offset_px):
        skipped[station] = False
    return replace(m, offsets_px=offsets, skipped=skipped, edge_sources=sources)


def set_offset(m: Measurement, station: int, side: int, offset_px: float) -> Measurement:
    """Place side ``side`` (0 = A, 1 = B) of ``station`` at ``offset_px`` by a click (NaN
    removes it).

    Placing an edge un-skips the station.
    """
    return _with_edge(m, station, side, offset_px, EDGE_CLICKED)


def move_offset(m: Measurement, station: int, side: int, offset_px: float) -> Measurement:
    """``set_offset`` for a drag or nudge: a suggested edge becomes suggested then moved; any
    other keeps its source."""
    return _with_edge(m, station, side, offset_px, moved_source(m.edge_sources[station, side]))


def set_skipped(m: Measurement, station: int, is_skipped: bool) -> Measurement:
    """Mark ``station`` not measurable (its handles are kept, and come back on un-skip)."""
    skipped = m.skipped.copy()
    skipped[station] = is_skipped
    return replace(m, skipped=skipped)


def set_mirror_side(m: Measurement, side: str | None) -> Measurement:
    """Measure both sides (None) or one side doubled ("A" or "B")."""
    return replace(m, mirror_side=side)


def offsets_from_edges(m: Measurement, edges_px: np.ndarray,
                       only_missing: bool = True) -> Measurement:
    """Offsets from edge points suggested from a mask (``suggested_edges``), recorded as
    suggested; NaN edges change nothing.

    ``only_missing``: keep the edges already placed.
    """
    stations = stations_of(m)
    if stations is None:
        raise ValueError("edges need a midline with at least two points")
    suggested = edge_offsets(stations, edges_px)
    keep = np.isnan(suggested) | (np.isfinite(m.offsets_px) if only_missing else False)
    return replace(m, offsets_px=np.where(keep, m.offsets_px, suggested),
                   edge_sources=np.where(keep, m.edge_sources, EDGE_SUGGESTED))
