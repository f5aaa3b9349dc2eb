"""The mask back-ends by name: the network tracker (default), the colour tracker (fast) and,
for users who installed it, SAM-2 (the paper's segmenter; core/segment/sam2_backend.py).

The name is what a user picks (CLI ``--backend``, the app's tracking menu) and what a mask
file records as its source. The network needs its installed weights, SAM-2 its package and a
checkpoint the user names; when they are missing the error says how to install them rather
than silently falling back to another back-end.
"""

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from dolphinfit.core.errors import InputError
from dolphinfit.core.segment.segmenter import Segmenter

if TYPE_CHECKING:
    import torch

NETWORK = "network"
NETWORK_COLOUR_EDGES = "network-colour-edges"
NETWORK_AS_DRAWN = "network-as-drawn"
COLOUR = "colour"
SAM2 = "sam2"
BACKENDS: dict[str, str] = {
    NETWORK: "salient-object network (U²-Net small) on a crop around the animal, the outline "
             "drawn by the project's edge network, then moved to where the image's step from "
             "body to water is half-way; about 0.4 s per 1080p frame and 0.8 s per 4K frame "
             "on two cores",
    NETWORK_AS_DRAWN: "the same network with the outline as the edge network draws it (the "
                      "default before the outline was fitted to the image's edge)",
    NETWORK_COLOUR_EDGES: "the same network with the outline placed by colour near its edge "
                          "(the default before the edge network)",
    COLOUR: "colour models of the animal and the water; fast (about 0.05 s per frame) but "
            "loses light-grey flukes over green water",
    SAM2: "SAM-2's video predictor from a click or a box (the sam2 package and a checkpoint, "
          "both installed by the user); slow on the CPU, so only on the frames to be fitted",
}
DEFAULT_BACKEND = NETWORK
# need only dolphinfit's own files
ALWAYS_AVAILABLE = (NETWORK, NETWORK_AS_DRAWN, NETWORK_COLOUR_EDGES, COLOUR)


def make_segmenter(backend: str = DEFAULT_BACKEND, only_frames: Sequence[int] | None = None,
                   checkpoint: Path | str | None = None,
                   device: "torch.device | str" = "cpu") -> Segmenter:
    """A segmenter of ``backend``; ``only_frames`` limits the network and SAM-2 to those
    frames (the colour tracker is cheap enough to run on every frame and ignores it).
    ``checkpoint``: SAM-2's checkpoint file, required for it (the others ignore it).
    ``device`` (core.device): where the edge network and SAM-2 run; the salient network
    (OpenCV) and the colour tracker always run on the CPU."""
    if backend in (NETWORK, NETWORK_COLOUR_EDGES, NETWORK_AS_DRAWN):
        from dolphinfit.core.segment.edge_steps import make_edge_step
        from dolphinfit.core.segment.net_settings import NetSettings
        from dolphinfit.core.segment.net_tracker import NetTracker
        settings = NetSettings(edges="colour" if backend == NETWORK_COLOUR_EDGES else "network",
                               fit_outline=backend != NETWORK_AS_DRAWN)
        return NetTracker(settings, only_frames=only_frames,
                          edges=make_edge_step(settings, device))
    if backend == COLOUR:
        from dolphinfit.core.segment.tracker import MaskTracker
        return MaskTracker()
    if backend == SAM2:
        if checkpoint is None:
            raise InputError(f"mask back-end {SAM2!r}: needs a SAM-2 checkpoint file (.pt)")
        from dolphinfit.core.segment.sam2_backend import Sam2Segmenter
        return Sam2Segmenter(checkpoint, only_frames, device=device)
    raise InputError(f"mask back-end {backend!r}: unknown; choose one of "
                     f"{', '.join(BACKENDS)}")
