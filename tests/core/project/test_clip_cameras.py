"""Clips' cameras as the user sets them: typed values are not approximate (in the project
file and the error model too), and one camera set on several clips, by selection and by
video size, with their lenses, in one step that marks their fits out of date."""

import json
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import cv2
import numpy as np
import pytest

from dolphinfit.core.camera_presets import DEFAULT_PRESET, get_preset
from dolphinfit.core.fit.pipeline import CameraChoice
from dolphinfit.core.measure.lens import LensModel
from dolphinfit.core.measure.preset_lens import store_preset_lens
from dolphinfit.core.measure.records import default_error_model
from dolphinfit.core.measure.uncertainty import FOCAL_SD_FRACTION, FOCAL_SD_FRACTION_APPROXIMATE
from dolphinfit.core.project.clip_cameras import (
    camera_setting, entered_camera, lens_with_camera, with_camera_setting,
)
from dolphinfit.core.project.fit_inputs import changed_since_fit, fit_inputs_of
from dolphinfit.core.project.model import Animal, ClipEntry, Project
from dolphinfit.core.project.new_project import default_camera
from dolphinfit.core.project.project_file import read_project, write_project

SMALL, LARGE = (320, 240), (640, 480)
ALTITUDE_M = 20.0


def test_typed_focal_and_sensor_are_not_approximate():
    """The fallback camera is approximate; typing a focal length and sensor width makes it
    the user's own, with the focal length and GSD those values give."""
    fallback, name = default_camera(1920, 1080)
    assert fallback.approximate and name is None
    typed = entered_camera(fallback, False, 8.8, 13.2, 1920, 1080, "test")
    assert not typed.approximate
    assert typed.intrinsics().focal_px == pytest.approx(1280.0)  # 8.8 / 13.2 × 1920
    assert typed.intrinsics().gsd_m_per_px(ALTITUDE_M) == pytest.approx(ALTITUDE_M / 1280.0)
    # only the focal length typed: the user's values too
    assert not entered_camera(fallback, False, 9.0, fallback.sensor_width_mm, 1920, 1080,
                              "test").approximate


def test_a_new_image_size_alone_verifies_nothing():
    """An approximate camera stays so at another size; a verified preset taken to another
    size becomes approximate (its sensor crop in that mode is unknown); typed values stay
    the user's at any size."""
    fhd, verified = get_preset("dji-mavic3-fhd"), get_preset(DEFAULT_PRESET)
    assert fhd.approximate and not verified.approximate
    assert entered_camera(fhd, True, fhd.focal_mm, fhd.sensor_width_mm, 1280, 720,
                          "test").approximate
    assert entered_camera(verified, True, verified.focal_mm, verified.sensor_width_mm, 1280,
                          720, "test").approximate
    typed = entered_camera(verified, True, 8.8, 13.2, 5120, 2700, "test")
    assert not entered_camera(typed, False, 8.8, 13.2, 1280, 720, "test").approximate


def test_the_flag_reaches_the_project_file_and_the_error_model(tmp_path):
    """A typed camera is written ``"approximate": false`` and read back so; its focal SD is
    the calibrated one (0.5 %), the fallback's the approximate one (2 %)."""
    fallback, _ = default_camera(1920, 1080)
    typed = entered_camera(fallback, False, 8.8, 13.2, 1920, 1080, "test")
    path = tmp_path / "p.dolphinfit"
    write_project(path, Project(clips=(
        ClipEntry("a.png", "image", typed), ClipEntry("b.png", "image", fallback))))
    cameras = [clip["camera"] for clip in json.loads(path.read_text())["clips"]]
    assert [(c["focal_mm"], c["sensor_width_mm"], c["approximate"]) for c in cameras] == [
        (8.8, 13.2, False), (fallback.focal_mm, fallback.sensor_width_mm, True)]
    again = read_project(path)
    assert [c.camera.approximate for c in again.clips] == [False, True]
    assert default_error_model("barometer", again.clips[0].camera.approximate
                               ).focal_sd_fraction == FOCAL_SD_FRACTION == 0.005
    assert default_error_model("barometer", again.clips[1].camera.approximate
                               ).focal_sd_fraction == FOCAL_SD_FRACTION_APPROXIMATE == 0.02


def test_the_command_line_follows_the_same_rule():
    """CameraChoice: explicit values are calibrated; a preset carries its own flag, and is
    approximate at another frame size than its own (the default 5.1K camera on a 1080p
    clip, as the app's default camera there)."""
    uhd, fhd = SimpleNamespace(width_px=5120, height_px=2700), SimpleNamespace(
        width_px=1920, height_px=1080)
    assert not CameraChoice(sensor_width_mm=13.2, focal_mm=8.8).is_approximate(fhd)
    assert CameraChoice(preset="dji-mavic3-fhd").is_approximate(fhd)
    assert not CameraChoice(preset=DEFAULT_PRESET).is_approximate(uhd)
    assert CameraChoice(preset=DEFAULT_PRESET).is_approximate(fhd)
    assert CameraChoice().is_approximate(fhd)


def _still(folder: Path, name: str, size: tuple[int, int]) -> str:
    cv2.imwrite(str(folder / name), np.zeros((size[1], size[0], 3), np.uint8))
    return name


@pytest.fixture
def stills(tmp_path) -> tuple[Path, Project]:
    """A project of four stills, three 320×240 and one 640×480, each with the fallback
    camera, and a fifth whose file is gone; the first clip's animal has a fit."""
    clips = [ClipEntry(_still(tmp_path, f"{n}.png", size), "image", default_camera(*size)[0])
             for n, size in zip("abcd", (SMALL, SMALL, SMALL, LARGE))]
    clips.append(ClipEntry("gone.png", "image", default_camera(*SMALL)[0]))
    project = Project(clips=tuple(clips))
    fitted = Animal("dolphin 1", fit_path="p.fits/a_dolphin-1",
                    fit_inputs=fit_inputs_of(project, clips[0]))
    project = Project(clips=(replace(clips[0], animals=(fitted,)), *clips[1:]))
    return tmp_path / "p.dolphinfit", project


def test_a_camera_set_on_selected_clips_in_one_step(stills):
    """Two selected clips take the camera; the others keep theirs; the fit is out of date."""
    path, project = stills
    camera = entered_camera(project.clips[0].camera, False, 8.8, 13.2, *SMALL, "test")
    setting = camera_setting(path, project, camera, None, [0, 3], {}, None)
    assert sorted(setting.lenses) == [0, 3]
    assert setting.notes == ("the camera is for 320×240 px images; these clips are not: d.png",)
    after = with_camera_setting(project, setting)
    assert [c.camera == camera for c in after.clips] == [True, False, False, True, False]
    assert changed_since_fit(after, after.clips[0], after.clips[0].animals[0]) == ["camera"]
    assert changed_since_fit(project, project.clips[0], project.clips[0].animals[0]) == []


def test_every_clip_of_one_size_takes_the_camera(stills):
    """With a video size, every clip of that size is set, one whose media is gone is said."""
    path, project = stills
    camera = entered_camera(project.clips[0].camera, False, 8.8, 13.2, *SMALL, "test")
    setting = camera_setting(path, project, camera, None, [0], {0: SMALL}, SMALL)
    assert sorted(setting.lenses) == [0, 1, 2]
    assert len(setting.notes) == 1 and setting.notes[0].startswith("gone.png left as it was: ")
    after = with_camera_setting(project, setting)
    assert [c.camera.focal_mm for c in after.clips] == [8.8, 8.8, 8.8, 12.29, 12.29]
    assert not any(c.camera.approximate for c in after.clips[:3])
    # the project changed meanwhile (a clip removed): the setting no longer applies
    assert with_camera_setting(Project(clips=project.clips[1:]), setting) is None


def test_each_clip_keeps_its_own_lens_or_takes_the_presets(stills):
    """A clip's own lens stays; the preset's lens comes where it is of the clip's size, and
    is left out, with the reason, where it is not."""
    path, project = stills
    preset = replace(default_camera(*SMALL)[0], name="my-drone", source="test")
    preset_lens = LensModel(*SMALL, 250.0, 250.0, 159.5, 119.5, (-0.1, 0.0, 0.0, 0.0, 0.0),
                            0.05, 9, "test")
    store_preset_lens(preset, preset_lens)
    own = replace(preset_lens, fx_px=260.0, fy_px=260.0)
    with_own = replace(project.clips[1], lens=own)
    assert lens_with_camera(with_own, "my-drone", SMALL) == (own, "")
    assert lens_with_camera(project.clips[2], "my-drone", SMALL) == (preset_lens, "")
    lens, note = lens_with_camera(project.clips[3], "my-drone", LARGE)
    assert lens is None and note.startswith("d.png: the lens model kept with 'my-drone'")
    assert "320×240" in note and "the camera is set without it" in note
