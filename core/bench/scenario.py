"""A named synthetic clip of a benchmark suite, where its rendered files are cached, and the
renderers that draw them.

Clips are drawn by dolphinfit's own renderer (``core.synth``) unless a scenario names
another; a renderer outside the engine (VTK's, ``dolphinfit.vtk_clips``, which the engine
never imports) registers its clip maker here when it is imported.
"""

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.pipeline import CameraChoice
from dolphinfit.core.progress import ProgressCallback
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import OWN_RENDERER, ClipFiles, clip_files, made_from
from dolphinfit.core.synth.sample import cache_dir, ensure_clip
from dolphinfit.core.synth.water import with_water

SUITE_NAME = "bench-suite-v2"          # the tuning split with the template's shapes
ClipMaker = Callable[[SynthConfig, Path, ProgressCallback | None], ClipFiles]
_RENDERERS: dict[str, ClipMaker] = {}


@dataclass(frozen=True)
class Scenario:
    """A named clip of the suite, what it shows, and the cache folder of its suite."""

    name: str
    config: SynthConfig
    shows: str
    suite: str = SUITE_NAME
    renderer: str = OWN_RENDERER


def scenario_maker(base: SynthConfig, suite: str = SUITE_NAME,
                   renderer: str = OWN_RENDERER) -> Callable[..., Scenario]:
    """``make(name, water, shows, **options)``: a scenario of ``suite`` drawn by ``renderer``,
    its configuration ``base`` with ``options`` over the named water."""
    def make(name: str, water: str, shows: str, **options) -> Scenario:
        return Scenario(name, with_water(replace(base, **options), water), shows, suite,
                        renderer)
    return make


def ensure_scenario(scenario: Scenario,
                    progress: ProgressCallback | None = None) -> ClipFiles:
    """One scenario's clip, rendered first by its renderer if it is missing or was made from
    another configuration or by another renderer (only rendering loads the model stack).
    InputError where its renderer is not registered (``register_renderer``)."""
    out_dir = cache_dir() / scenario.suite / scenario.name
    if scenario.renderer == OWN_RENDERER:
        return ensure_clip(scenario.config, out_dir, progress)
    files = clip_files(out_dir, scenario.config)
    if made_from(files, scenario.config, scenario.renderer):
        return files
    if scenario.renderer not in _RENDERERS:
        raise InputError(f"{scenario.name}: drawn by the {scenario.renderer!r} renderer, which "
                         f"is not loaded (import dolphinfit.vtk_clips first)")
    out_dir.mkdir(parents=True, exist_ok=True)
    return _RENDERERS[scenario.renderer](scenario.config, out_dir, progress)


def register_renderer(name: str, maker: ClipMaker) -> None:
    """Let scenarios drawn by ``name`` be made by ``maker(config, out_dir, progress)``."""
    _RENDERERS[name] = maker


def synth_camera(config: SynthConfig) -> CameraChoice:
    """The camera a synthetic clip was rendered with, as a fit is told it."""
    return CameraChoice(sensor_width_mm=config.sensor_width_mm, focal_mm=config.focal_mm)
