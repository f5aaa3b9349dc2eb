"""The sample project that ``make run`` opens: the synthetic sample clip (rendered into the
cache on first use), its DJI SRT with the launch height, its camera, its masks (for edge
suggestions) and one animal to measure."""

from pathlib import Path

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.progress import ProgressCallback
from dolphinfit.core.project.model import AltitudeSpec, Animal, ClipEntry, Project
from dolphinfit.core.project.project_file import PROJECT_SUFFIX, relative_media_path, write_project
from dolphinfit.core.synth.sample import SAMPLE_CONFIG, SAMPLE_NAME, ensure_sample


def sample_project(video: Path, srt: Path, masks: Path, project_dir: Path) -> Project:
    """The sample's project tree: camera and altitude as the clip was made, nothing measured."""
    config = SAMPLE_CONFIG
    camera = CameraPreset(
        name=SAMPLE_NAME, description="the sample clip's simulated camera",
        focal_mm=config.focal_mm, sensor_width_mm=config.sensor_width_mm,
        image_width_px=config.width_px, image_height_px=config.height_px,
        source="core/synth/sample.py", approximate=False)
    altitude = AltitudeSpec(path=relative_media_path(project_dir, srt),
                            launch_height_m=config.launch_height_m, source="barometer")
    clip = ClipEntry(media_path=relative_media_path(project_dir, video), kind="video",
                     camera=camera, altitude=altitude, animals=(Animal("dolphin 1"),),
                     masks_path=relative_media_path(project_dir, masks))
    return Project(clips=(clip,))


def ensure_sample_project(progress: ProgressCallback | None = None) -> Path:
    """The sample project file, written beside the cached sample clip when missing
    (``progress`` is called while the clip renders)."""
    files = ensure_sample(progress)
    path = files.video.parent / f"sample{PROJECT_SUFFIX}"
    if not path.exists():
        write_project(path, sample_project(files.video, files.srt, files.masks_dir, path.parent))
    return path
