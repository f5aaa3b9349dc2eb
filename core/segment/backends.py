"""The mask back-ends by name: the network tracker (default) and the colour tracker (fast).

The name is what a user picks (CLI ``--backend``, the app's tracking menu) and what a mask
file records as its source. The network needs its installed weights; when they are missing
the error says how to install them rather than silently falling back to colour.
"""

from collections.abc import Sequence

from core.errors import InputError
from core.segment.segmenter import Segmenter

NETWORK = "network"
COLOUR = "colour"
BACKENDS: dict[str, str] = {
    NETWORK: "salient-object network (U²-Net small) on a crop around the animal, edges "
             "placed by colour; about 0.3–0.9 s per frame on two cores",
    COLOUR: "colour models of the animal and the water; fast (about 0.05 s per frame) but "
            "loses light-grey flukes over green water",
}
DEFAULT_BACKEND = NETWORK


def make_segmenter(backend: str = DEFAULT_BACKEND,
                   only_frames: Sequence[int] | None = None) -> Segmenter:
    """A segmenter of ``backend``; ``only_frames`` limits the network to those frames (the
    colour tracker is cheap enough to run on every frame and ignores it)."""
    if backend == NETWORK:
        from core.segment.net_tracker import NetTracker
        return NetTracker(only_frames=only_frames)
    if backend == COLOUR:
        from core.segment.tracker import MaskTracker
        return MaskTracker()
    raise InputError(f"mask back-end {backend!r}: unknown; choose one of "
                     f"{', '.join(BACKENDS)}")
