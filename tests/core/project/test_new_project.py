"""Starting a project from media: where its file goes, its camera, adding media once."""

import cv2
import numpy as np

from dolphinfit.core.camera_presets import DEFAULT_PRESET, get_preset
from dolphinfit.core.io.media import open_media
from dolphinfit.core.project.model import CAMERA_UNKNOWN, Project
from dolphinfit.core.project.new_project import (
    clip_entry_for, default_camera, project_path_for, project_with_clip,
)


def test_project_file_sits_beside_the_media(tmp_path):
    clip = tmp_path / "DJI_0042.MP4"
    clip.write_bytes(b"x")
    frames = tmp_path / "frames"
    frames.mkdir()
    assert project_path_for(clip) == tmp_path / "DJI_0042.dolphinfit"
    assert project_path_for(frames) == tmp_path / "frames.dolphinfit"


def test_default_camera_keeps_the_preset_only_at_its_own_size():
    preset = get_preset(DEFAULT_PRESET)
    same, name = default_camera(preset.image_width_px, preset.image_height_px)
    assert (same, name) == (preset, DEFAULT_PRESET)
    other, name = default_camera(1280, 720)
    assert name is None and other.approximate
    assert (other.image_width_px, other.focal_mm) == (1280, preset.focal_mm)


def test_media_is_added_once_with_a_relative_path(tmp_path):
    """A still without EXIF, of no preset's size, is added with its camera unknown."""
    image = tmp_path / "stills" / "a.png"
    image.parent.mkdir()
    cv2.imwrite(str(image), np.zeros((40, 60, 3), np.uint8))
    with open_media(image) as source:
        entry, note = clip_entry_for(image, tmp_path, source)
    project, idx = project_with_clip(Project(), entry)
    again, again_idx = project_with_clip(project, entry)
    assert idx == again_idx == 0 and again is project
    clip = project.clips[0]
    assert (clip.media_path, clip.kind) == ("stills/a.png", "image")
    assert clip.camera is None and clip.preset_name is None
    assert CAMERA_UNKNOWN in note and "a.png has no EXIF" in note
