"""One task of a batch: one animal in one clip, fitted by the 3D model and measured by the
elliptical method, with its own output folder."""

from dataclasses import dataclass
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.pipeline import CameraChoice
from dolphinfit.core.measure.altitude_calibration import AltitudeCalibration
from dolphinfit.core.measure.elliptical import TAIL_EXTRAPOLATED
from dolphinfit.core.measure.lens import LensModel
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET
from dolphinfit.core.measure.uncertainty import DEFAULT_NUM_DRAWS
from dolphinfit.core.project.model import Project
from dolphinfit.core.segment.segmenter import AutoSeed, Seed


@dataclass(frozen=True)
class FitInputs:
    """What ``core.fit.pipeline.run_fit`` needs: the clip, its altitude (metres, an altitude
    CSV, DJI SRT or laser log, or None for the clip's SRT sidecar) and its calibration, the
    camera and its lens model, and the masks or, without them, the tracker's seed and the
    frames it tracks besides the fit's (``also_frames``: those the elliptical method
    measures)."""

    clip: Path
    altitude: float | Path | None
    launch_height_m: float = 0.0
    time_offset_s: float = 0.0
    camera: CameraChoice = CameraChoice()
    masks: Path | None = None
    seed: Seed = AutoSeed()
    config: FitConfig = FitConfig()
    altitude_calibration: AltitudeCalibration | None = None
    also_frames: tuple[int, ...] = ()
    lens: LensModel | None = None


@dataclass(frozen=True)
class MaskMeasurement:
    """The elliptical baseline taken from the fit's masks: length and widths from the mask of
    each of ``frames`` (a scan's best frames), or where none are given, of the fitted frame
    where the most of the animal is seen (core/batch/mask_baseline.py); through ``lens``
    where given."""

    altitude_source: str = "manual"
    hw: str = DEFAULT_PRESET
    tail: str = TAIL_EXTRAPOLATED
    num_draws: int = DEFAULT_NUM_DRAWS
    frames: tuple[int, ...] = ()
    lens: LensModel | None = None


@dataclass(frozen=True, eq=False)
class ProjectMeasurement:
    """The elliptical baseline of the frames the user measured on an animal of a project."""

    project: Project
    project_path: Path
    clip_idx: int
    animal_idx: int
    num_draws: int = DEFAULT_NUM_DRAWS


@dataclass(frozen=True, eq=False)
class BatchTask:
    """``name``: the task's folder under the batch's output folder (unique in a batch);
    ``clip``: the clip as the manifest or project names it; ``where``: the manifest row or
    project entry it came from, for messages. ``fit`` is None where there is nothing to fit
    (a still image)."""

    name: str
    clip: str
    animal_id: str
    where: str
    fit: FitInputs | None
    measurement: MaskMeasurement | ProjectMeasurement


def check_unique_names(tasks: list[BatchTask]) -> list[BatchTask]:
    """``tasks`` if no two share an output folder; InputError naming both otherwise (IDs that
    differ only by a space and a dash name the same folder)."""
    seen: dict[str, BatchTask] = {}
    for task in tasks:
        if task.name in seen:
            raise InputError(f"{task.where}: {task.clip} {task.animal_id!r} would share the "
                             f"output folder {task.name} with {seen[task.name].where}")
        seen[task.name] = task
    return tasks
