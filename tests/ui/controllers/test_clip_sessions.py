"""The open clip's session, built without the window: opened when a clip is selected, its
altitude read again when the project's setting changes (and when that is undone), the Clip
menu's altitude, camera and lens commands asked and done apart."""

import shutil
from pathlib import Path

import pytest
from PySide6.QtWidgets import QWidget

from dolphinfit.core.project.model import AltitudeSpec
from dolphinfit.core.project.project_file import read_project
from dolphinfit.core.project.sample import ensure_sample_project
from dolphinfit.ui.controllers.clip_sessions import ClipSessions
from dolphinfit.ui.dialogs.camera_dialog import CameraAnswer
from dolphinfit.ui.dialogs.questions import Questions
from dolphinfit.ui.state.project_model import ProjectModel
from dolphinfit.ui.state.viewer_state import Notifier, ViewerState
from dolphinfit.ui.workers.background import BackgroundJobs

TIMEOUT_MS = 30_000


class _Answers(Questions):
    """The questions answered by the test: the altitude it was given."""

    def __init__(self, parent: QWidget, altitude: AltitudeSpec) -> None:
        super().__init__(parent)
        self.answer = altitude

    def altitude(self, media: Path, project_dir: Path, clip, current):
        return self.answer

    def lens_file(self) -> Path | None:
        return self.lens

    def camera(self, camera, preset_name, width_px, height_px, num_clips):
        return self.chosen_camera


@pytest.fixture
def sessions(qtbot, tmp_path):
    parent = QWidget()
    qtbot.addWidget(parent)
    sample = ensure_sample_project()   # copied: edits autosave beside the project
    shutil.copytree(sample.parent, tmp_path / "sample",
                    ignore=shutil.ignore_patterns("*.autosave"))
    path = tmp_path / "sample" / sample.name
    model = ProjectModel(read_project(path), path, parent=parent)
    state, notifier = ViewerState(parent), Notifier(parent)
    errors = []
    notifier.error_raised.connect(lambda title, text: errors.append(f"{title}: {text}"))
    controller = ClipSessions(model, state, _Answers(parent, AltitudeSpec(constant_m=30.0)),
                              notifier, BackgroundJobs(parent), parent=parent)
    yield controller, errors
    controller.close()
    controller.jobs.wait()


def test_selecting_a_clip_opens_it_and_answers_its_altitudes(qtbot, sessions):
    controller, errors = sessions
    controller.model.select(0)
    with qtbot.waitSignal(controller.opened, timeout=TIMEOUT_MS) as opened:
        controller.open_current()
    assert opened.args[0] is controller.state.session and not errors
    altitude, source = controller.altitude_at(0, 10)
    assert 15.0 < altitude < 25.0 and source == "barometer"   # the sample's SRT at ~20 m


def test_a_new_altitude_is_read_again_and_its_undo_too(qtbot, sessions):
    controller, errors = sessions
    controller.model.select(0)
    with qtbot.waitSignal(controller.opened, timeout=TIMEOUT_MS):
        controller.open_current()
    before = controller.altitude_at(0, 10)[0]
    with qtbot.waitSignal(controller.telemetry_changed, timeout=TIMEOUT_MS):
        controller.set_altitude()
    assert controller.altitude_at(0, 10)[0] == 30.0
    with qtbot.waitSignal(controller.telemetry_changed, timeout=TIMEOUT_MS):
        controller.model.undo_stack.undo()
    assert controller.altitude_at(0, 10)[0] == before and not errors


def test_a_lens_model_of_the_clips_size_is_taken_and_undone(qtbot, sessions, tmp_path):
    from dataclasses import replace

    from dolphinfit.core.measure.lens import LensModel, write_lens

    controller, errors = sessions
    controller.model.select(0)
    with qtbot.waitSignal(controller.opened, timeout=TIMEOUT_MS):
        controller.open_current()
    media = controller.state.session.source.clip
    lens = LensModel(media.width_px, media.height_px, 900.0, 900.0, 639.5, 359.5,
                     (-0.1, 0.02, 0.0, 0.0, 0.0), 0.05, 9, "test")
    write_lens(lens, tmp_path / "lens.json")
    controller.ask.lens = tmp_path / "lens.json"
    assert controller.model.project.clips[0].lens is None
    controller.set_lens()
    qtbot.waitUntil(lambda: controller.model.project.clips[0].lens == lens, timeout=TIMEOUT_MS)
    controller.model.undo_stack.undo()
    assert controller.model.project.clips[0].lens is None
    # a lens of another video mode is refused, naming the file
    write_lens(replace(lens, width_px=1920, height_px=1080), tmp_path / "other.json")
    controller.ask.lens = tmp_path / "other.json"
    controller.set_lens()
    qtbot.waitUntil(lambda: len(errors) > 0, timeout=TIMEOUT_MS)
    assert "Lens model: " in errors[0] and "other.json: the lens was calibrated on 1920×1080" \
        in errors[0] and controller.model.project.clips[0].lens is None


def test_a_preset_keeping_a_lens_gives_it_to_the_clip_in_the_same_step(qtbot, sessions):
    """Clip → Camera… with a preset that keeps a lens model (`dolphinfit camera lens`): the
    clip takes camera and lens in one undoable edit."""
    from dataclasses import replace

    from dolphinfit.core.camera_presets import save_user_preset
    from dolphinfit.core.measure.lens import LensModel
    from dolphinfit.core.measure.preset_lens import store_preset_lens

    controller, errors = sessions
    controller.model.select(0)
    with qtbot.waitSignal(controller.opened, timeout=TIMEOUT_MS):
        controller.open_current()
    clip = controller.model.project.clips[0]
    preset = replace(clip.camera, name="my-drone-720p", description="", source="test")
    save_user_preset(preset)
    lens = LensModel(1280, 720, 900.0, 900.0, 639.5, 359.5, (-0.1, 0.02, 0.0, 0.0, 0.0), 0.05,
                     9, "test")
    store_preset_lens(preset, lens)
    controller.ask.chosen_camera = CameraAnswer(preset, preset.name)
    controller.set_camera()
    qtbot.waitUntil(lambda: controller.model.project.clips[0].lens == lens, timeout=TIMEOUT_MS)
    assert controller.model.project.clips[0].preset_name == "my-drone-720p" and not errors
    controller.model.undo_stack.undo()
    assert controller.model.project.clips[0].lens is None
    assert controller.model.project.clips[0].preset_name == clip.preset_name
