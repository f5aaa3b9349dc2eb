"""Starting a project from media: a clip, a still image or a folder of numbered frames.

Opening media that has no project yet starts one whose file will sit beside it
(``DJI_0042.MP4`` → ``DJI_0042.dolphinfit``), so autosave protects the work from the first
click; an existing project of that name is opened instead.

A still takes the camera its EXIF names (core.project.photo_camera), else the one preset of
its size, else none: a video preset's lens would give every length wrong, so the clip's
camera stays unknown until the user sets it. Videos and frame folders take the default
camera (:func:`default_camera`).
"""

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from dolphinfit.core.camera_presets import (
    DEFAULT_PRESET, CameraPreset, get_preset, load_presets,
)
from dolphinfit.core.io.media import FrameSource
from dolphinfit.core.io.media_fingerprint import media_fingerprint
from dolphinfit.core.project.model import CAMERA_UNKNOWN, ClipEntry, Project, add_clip
from dolphinfit.core.project.photo_camera import photo_camera
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


@dataclass(frozen=True)
class MediaCamera:
    """The camera media is added with (None: unknown), its preset's name, and what the user
    is told of it ("" where nothing)."""

    camera: CameraPreset | None
    preset_name: str | None
    note: str


def still_camera(path: Path, width_px: int, height_px: int,
                 presets: Mapping[str, CameraPreset]) -> MediaCamera:
    """The module doc's camera of a still: its EXIF's, the one preset of its size, or none."""
    camera, why = photo_camera(path, width_px, height_px)
    if camera is not None:
        return MediaCamera(camera, None, why)
    matches = [name for name, p in presets.items()
               if (p.image_width_px, p.image_height_px) == (width_px, height_px)]
    if len(matches) == 1:
        return MediaCamera(presets[matches[0]], matches[0],
                           f"{why}; {matches[0]}: the only preset at {width_px}×{height_px} px")
    return MediaCamera(None, None, f"{path.name}: {CAMERA_UNKNOWN} ({why})")


def clip_entry_for(media_path: Path, project_dir: Path,
                   source: FrameSource) -> tuple[ClipEntry, str]:
    """A new clip entry for opened media, with its camera (module doc) and no altitude yet,
    and what the user is told of its camera. Reads the media (run it off the GUI thread)."""
    width_px, height_px = source.clip.width_px, source.clip.height_px
    if source.kind == "image":
        found = still_camera(media_path, width_px, height_px, load_presets())
    else:
        found = MediaCamera(*default_camera(width_px, height_px), "")
    entry = ClipEntry(media_path=relative_media_path(project_dir, media_path),
                      kind=source.kind, camera=found.camera, preset_name=found.preset_name,
                      media_fingerprint=media_fingerprint(media_path))
    return entry, found.note


def project_with_clip(project: Project, entry: ClipEntry) -> tuple[Project, int]:
    """``project`` with ``entry`` added (or the clip that already holds its media), and its
    index."""
    for idx, clip in enumerate(project.clips):
        if clip.media_path == entry.media_path:
            return project, idx
    return add_clip(project, entry), len(project.clips)
