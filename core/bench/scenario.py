"""A named synthetic clip of a benchmark suite, and where its rendered files are cached."""

from dataclasses import dataclass

from dolphinfit.core.fit.pipeline import CameraChoice
from dolphinfit.core.progress import ProgressCallback
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import ClipFiles
from dolphinfit.core.synth.sample import cache_dir, ensure_clip

SUITE_NAME = "bench-suite-v2"          # the tuning split with the template's shapes


@dataclass(frozen=True)
class Scenario:
    """A named clip of the suite, what it shows, and the cache folder of its suite."""

    name: str
    config: SynthConfig
    shows: str
    suite: str = SUITE_NAME


def ensure_scenario(scenario: Scenario,
                    progress: ProgressCallback | None = None) -> ClipFiles:
    """One scenario's clip, rendered first if it is missing or was made from another
    configuration (only rendering loads the model stack)."""
    return ensure_clip(scenario.config, cache_dir() / scenario.suite / scenario.name, progress)


def synth_camera(config: SynthConfig) -> CameraChoice:
    """The camera a synthetic clip was rendered with, as a fit is told it."""
    return CameraChoice(sensor_width_mm=config.sensor_width_mm, focal_mm=config.focal_mm)
