"""How each width edge was placed, kept with the measurement and written beside its width.

Three sources, per station and side: ``clicked`` (placed by the user), ``suggested`` (placed by
"Suggest edges from the mask" and not touched since) and ``suggested_moved`` (suggested, then
dragged or nudged by the user). Arrays of them are (S, 2) str, side A then side B, with
NO_EDGE where no edge is placed or none is used (a skipped station, the side a mirror leaves
out).
"""

import numpy as np

from dolphinfit.core.measure.annotation import SIDES
from dolphinfit.core.measure.morphometrix import width_name
from dolphinfit.core.measure.stations import STATION_PCT

EDGE_CLICKED = "clicked"
EDGE_SUGGESTED = "suggested"
EDGE_SUGGESTED_MOVED = "suggested_moved"
EDGE_SOURCES = (EDGE_CLICKED, EDGE_SUGGESTED, EDGE_SUGGESTED_MOVED)
NO_EDGE = ""
# wide enough for every source: a narrower array would truncate one assigned into it
EDGE_SOURCE_DTYPE = np.dtype(f"U{max(map(len, EDGE_SOURCES))}")
SOURCE_JSON_KEYS = tuple(f"side_{side.lower()}_source" for side in SIDES)  # per station


def moved_source(source: str) -> str:
    """The source of an edge after the user moved it: a suggested edge becomes
    ``suggested_moved``; any other stays as it was (an unplaced one counts as clicked)."""
    if source in (EDGE_SUGGESTED, EDGE_SUGGESTED_MOVED):
        return EDGE_SUGGESTED_MOVED
    return source or EDGE_CLICKED


def stations_sources_json(sources: np.ndarray) -> list[dict[str, str | None]]:
    """Per station of (S, 2) ``sources``: its two sides' sources, null for NO_EDGE."""
    return [{key: source or None for key, source in zip(SOURCE_JSON_KEYS, pair)}
            for pair in sources.tolist()]


def wide_source_columns(sources: np.ndarray, length_name: str) -> dict[str, str]:
    """Wide-CSV columns of (S, 2) ``sources``: ``TL_w05.00_A_source``, ``TL_w05.00_B_source``,
    … (empty: no edge used)."""
    return {f"{width_name(length_name, pct)}_{side}_source": source
            for pct, pair in zip(STATION_PCT.tolist(), sources.tolist())
            for side, source in zip(SIDES, pair)}
