"""The tasks of a project file: every animal of every clip, fitted with the animal's own fit
settings (as the app would fit it) and measured on the frames the user measured."""

from pathlib import Path

from dolphinfit.core.batch.task import BatchTask, FitInputs, ProjectMeasurement
from dolphinfit.core.fit.pipeline import CameraChoice
from dolphinfit.core.measure.uncertainty import DEFAULT_NUM_DRAWS
from dolphinfit.core.project.calibrations import fitted_calibration
from dolphinfit.core.project.fit_settings import fit_dir
from dolphinfit.core.project.results import project_fit_config
from dolphinfit.core.project.model import Animal, ClipEntry, Project
from dolphinfit.core.project.project_file import media_path, read_project


def _fit_inputs(project_path: Path, project: Project, clip: ClipEntry,
                animal: Animal) -> FitInputs | None:
    """The fit of a video clip's animal (None for stills and frame folders); without an
    altitude the clip's SRT sidecar is used, without masks the tracker finds the dolphin."""
    if clip.kind != "video":
        return None
    spec, project_dir = clip.altitude, project_path.parent
    altitude = (None if spec is None
                else spec.constant_m if spec.path is None else project_dir / spec.path)
    return FitInputs(
        clip=media_path(project_path, clip), altitude=altitude,
        launch_height_m=0.0 if spec is None else spec.launch_height_m,
        time_offset_s=0.0 if spec is None else spec.time_offset_s,
        camera=CameraChoice(None, clip.known_camera().sensor_width_mm,
                            clip.known_camera().focal_mm),
        masks=None if clip.masks_path is None else (project_dir / clip.masks_path).resolve(),
        config=project_fit_config(animal.fit_settings, project, project_dir),
        altitude_calibration=(None if clip.altitude_calibration is None else
                              fitted_calibration(project.calibration(clip.altitude_calibration))),
        lens=clip.lens)


def project_tasks(project_path: Path, num_draws: int = DEFAULT_NUM_DRAWS) -> list[BatchTask]:
    """One task per animal of the project file (InputError naming the file if unreadable)."""
    project_path = Path(project_path).resolve()
    project = read_project(project_path)
    return [BatchTask(name=fit_dir(project_path, clip.media_path, animal.animal_id).name,
                      clip=clip.media_path, animal_id=animal.animal_id,
                      where=f"{project_path}: clips[{c}] animals[{a}]",
                      fit=_fit_inputs(project_path, project, clip, animal),
                      measurement=ProjectMeasurement(project, project_path, c, a, num_draws))
            for c, clip in enumerate(project.clips) for a, animal in enumerate(clip.animals)]
