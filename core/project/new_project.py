"""Starting a project from media: a clip, a still image or a folder of numbered frames.

Opening media that has no project yet starts one whose file will sit beside it
(``DJI_0042.MP4`` → ``DJI_0042.dolphinfit``), so autosave protects the work from the first
click; an existing project of that name is opened instead.
"""

from pathlib import Path

from dolphinfit.core.camera_presets import DEFAULT_PRESET, CameraPreset, get_preset
from dolphinfit.core.io.media import FrameSource
from dolphinfit.core.io.media_fingerprint import media_fingerprint
from dolphinfit.core.project.model import ClipEntry, Project, add_clip
from dolphinfit.core.project.project_file import PROJECT_SUFFIX, relative_media_path


def project_path_for(media: Path) -> Path:
    """Where the project of ``media`` is kept: beside it, named after it."""
    media = Path(media).resolve()
    return media.parent / f"{media.stem if media.is_file() else media.name}{PROJECT_SUFFIX}"


def default_camera(width_px: int, height_px: int) -> tuple[CameraPreset, str | None]:
    """The default preset when its resolution matches the media, else its sensor and lens
    at the media's size (marked edited: the user is asked to check it)."""
    preset = get_preset(DEFAULT_PRESET)
    if (preset.image_width_px, preset.image_height_px) == (width_px, height_px):
        return preset, DEFAULT_PRESET
    return CameraPreset(
        name="edited", description=f"{preset.name} at {width_px}×{height_px} px",
        focal_mm=preset.focal_mm, sensor_width_mm=preset.sensor_width_mm,
        image_width_px=width_px, image_height_px=height_px, source=preset.source,
        approximate=True), None


def clip_entry_for(media_path: Path, project_dir: Path, source: FrameSource) -> ClipEntry:
    """A new clip entry for opened media, with the default camera and no altitude yet."""
    camera, preset_name = default_camera(source.clip.width_px, source.clip.height_px)
    return ClipEntry(media_path=relative_media_path(project_dir, media_path),
                     kind=source.kind, camera=camera, preset_name=preset_name,
                     media_fingerprint=media_fingerprint(media_path))


def project_with_media(project: Project, media_path: Path, project_dir: Path,
                       source: FrameSource) -> tuple[Project, int]:
    """``project`` with the media added (or the clip that already holds it), and its index."""
    rel = relative_media_path(project_dir, media_path)
    for idx, clip in enumerate(project.clips):
        if clip.media_path == rel:
            return project, idx
    return add_clip(project, clip_entry_for(media_path, project_dir, source)), len(project.clips)
