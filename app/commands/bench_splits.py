"""The renderers of the bench splits that the engine does not draw itself: the VTK split's
clips are drawn by ``dolphinfit.vtk_clips``, which the engine never imports."""

import importlib
from collections.abc import Iterable

from dolphinfit.core.bench.vtk_split import VTK_RENDERER


def load_renderers(splits: Iterable[str]) -> None:
    """Register the renderer of each split among ``splits`` drawn outside the engine."""
    if VTK_RENDERER in splits:
        importlib.import_module("dolphinfit.vtk_clips")   # registers the renderer
