"""Clips' cameras as the user sets them: values typed by hand, and one camera set on several
clips at once (the app's Clip → Camera… on clips selected together, or on every clip of one
video size) in one edit.

A camera is approximate only where its focal length and sensor width are a preset's marked
approximate, or a preset's taken at another video size than its own (as the default camera
of core.project.new_project); values the user types are the user's own, and count as
calibrated (as CameraChoice's explicit values in core.fit.pipeline).
"""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.media import open_media
from dolphinfit.core.measure.lens import LensModel
from dolphinfit.core.measure.preset_lens import preset_lens
from dolphinfit.core.project.model import ClipEntry, Project, with_clip
from dolphinfit.core.project.project_file import media_path

EDITED_NAME = "edited"  # the name of a camera whose values were typed
Size = tuple[int, int]  # (width, height) px


def entered_camera(based_on: CameraPreset | None, is_preset: bool, focal_mm: float,
                   sensor_width_mm: float, image_width_px: int, image_height_px: int,
                   source: str) -> CameraPreset:
    """The camera of values typed over ``based_on`` (a preset's where ``is_preset``; None: no
    camera, every value typed), by the module doc's rule: typed focal length or sensor width,
    not approximate; else ``based_on``'s flag, and approximate where a preset's are taken to
    another image size."""
    camera = CameraPreset(
        name=EDITED_NAME, description="values entered by hand", focal_mm=focal_mm,
        sensor_width_mm=sensor_width_mm, image_width_px=image_width_px,
        image_height_px=image_height_px, source=source, approximate=False)
    if based_on is None or (focal_mm, sensor_width_mm) != (based_on.focal_mm,
                                                          based_on.sensor_width_mm):
        return camera
    is_resized = (image_width_px, image_height_px) != (based_on.image_width_px,
                                                       based_on.image_height_px)
    return replace(camera, approximate=based_on.approximate or is_preset and is_resized)


@dataclass(frozen=True)
class CameraSetting:
    """A camera to set on clips: by clip index, the clip's media path (to check the project
    still holds that clip there) and the lens model it takes with the camera; ``notes``: what
    the user is told (clips left out, lens models left out, image sizes that differ)."""

    camera: CameraPreset
    preset_name: str | None
    media_paths: Mapping[int, str]
    lenses: Mapping[int, LensModel | None]
    notes: tuple[str, ...]


def media_size(project_path: Path, clip: ClipEntry) -> Size:
    """The clip's frame size read from its media; InputError naming it when unreadable."""
    with open_media(media_path(project_path, clip)) as source:
        return source.clip.width_px, source.clip.height_px


def _lens_of(preset_name: str | None) -> LensModel | None:
    """The lens kept with the preset; None also when unreadable (said where it is used)."""
    try:
        return preset_lens(preset_name)
    except InputError:
        return None


def lens_with_camera(clip: ClipEntry, preset_name: str | None, size: Size) -> tuple[
        LensModel | None, str]:
    """The lens model the clip takes with the camera of ``preset_name`` and a note: its own
    (one not kept with its old preset) stays; else the one kept with the new preset
    (core.measure.preset_lens), left out with the reason when unreadable or of another size
    than the clip's ``size``."""
    if clip.lens is not None and clip.lens != _lens_of(clip.preset_name):
        return clip.lens, ""
    try:
        lens = preset_lens(preset_name)
        if lens is not None:
            lens.check_image_size(*size, f"the lens model kept with {preset_name!r}")
    except InputError as exc:
        return None, f"{clip.name}: {exc}: the camera is set without it"
    return lens, ""


def _targets(project_path: Path, project: Project, selected: Sequence[int],
             known: Mapping[int, Size], every_of_size: Size | None) -> tuple[
                 dict[int, Size], list[str]]:
    """The clips to set with their frame sizes: ``selected``, and with ``every_of_size``
    every clip of that size; the clips whose media could not be read, as notes."""
    sizes, notes = {}, []
    candidates = range(len(project.clips)) if every_of_size is not None else selected
    for clip_idx in sorted(set(candidates) | set(selected)):
        clip = project.clips[clip_idx]
        try:
            size = known[clip_idx] if clip_idx in known else media_size(project_path, clip)
        except (InputError, OSError) as exc:
            notes.append(f"{clip.name} left as it was: {exc}")
            continue
        if clip_idx in selected or size == every_of_size:
            sizes[clip_idx] = size
    return sizes, notes


def camera_setting(project_path: Path, project: Project, camera: CameraPreset,
                   preset_name: str | None, selected: Sequence[int],
                   known: Mapping[int, Size], every_of_size: Size | None) -> CameraSetting:
    """The camera set on the ``selected`` clips and, with ``every_of_size``, on every clip of
    that frame size, each with its lens model (:func:`lens_with_camera`). Frame sizes are
    read from the media (I/O: run it in a worker) where ``known`` does not give them."""
    sizes, notes = _targets(project_path, project, selected, known, every_of_size)
    lenses = {}
    for clip_idx, size in sizes.items():
        lenses[clip_idx], note = lens_with_camera(project.clips[clip_idx], preset_name, size)
        if note:
            notes.append(note)
    camera_size = (camera.image_width_px, camera.image_height_px)
    other = [project.clips[i].name for i, size in sizes.items() if size != camera_size]
    if other:
        notes.append(f"the camera is for {camera_size[0]}×{camera_size[1]} px images; "
                     f"these clips are not: {', '.join(other)}")
    return CameraSetting(camera, preset_name,
                         {i: project.clips[i].media_path for i in sizes}, lenses, tuple(notes))


def with_camera_setting(project: Project, setting: CameraSetting) -> Project | None:
    """``project`` with the setting's clips given its camera and their lenses; None when one
    of them is no longer at its index (the project changed while the setting was made)."""
    clips = project.clips
    for clip_idx, lens in setting.lenses.items():
        if clip_idx >= len(clips) or clips[clip_idx].media_path != setting.media_paths[clip_idx]:
            return None
        project = with_clip(project, clip_idx, replace(
            clips[clip_idx], camera=setting.camera, preset_name=setting.preset_name, lens=lens))
    return project
