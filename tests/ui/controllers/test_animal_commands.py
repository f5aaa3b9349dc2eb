"""The animal and measured-frame commands, built without the window: each asks, then pushes
one undoable edit."""

from types import SimpleNamespace

from PySide6.QtWidgets import QWidget

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.project.model import ClipEntry, Project
from dolphinfit.ui.controllers.animal_commands import AnimalCommands
from dolphinfit.ui.dialogs.questions import Questions
from dolphinfit.ui.state.project_model import ProjectModel
from dolphinfit.ui.state.viewer_state import Notifier, ViewerState

CAMERA = CameraPreset("test", "", 12.29, 17.27, 1280, 720, "test", False)


class _Answers(Questions):
    def animal(self, animal, others):
        return ("Tursiops A", "nick in the dorsal fin")

    def remove_animal(self, animal):
        return True


def test_commands_edit_the_tree_and_undo(qtbot, tmp_path):
    parent = QWidget()
    qtbot.addWidget(parent)
    model = ProjectModel(Project(clips=(ClipEntry("a.mp4", "video", CAMERA),)),
                         tmp_path / "p.dolphinfit", parent=parent)
    state, notifier = ViewerState(parent), Notifier(parent)
    errors = []
    notifier.error_raised.connect(lambda title, text: errors.append(title))
    commands = AnimalCommands(model, state, _Answers(parent), notifier, parent=parent)
    empty = AnimalCommands(ProjectModel(Project(), None, parent=parent), state,
                           _Answers(parent), notifier, parent=parent)
    assert not empty.measure_frame() and errors == ["No clip"]   # no clip to measure on
    model.select(0)
    assert not commands.measure_frame()        # the clip is not on screen yet
    assert model.project.clips[0].animals == ()
    state.session, state.frame_idx = SimpleNamespace(clip_idx=0), 7   # a clip on screen
    assert commands.measure_frame()            # a first animal is made for it
    (animal,) = model.project.clips[0].animals
    assert [m.frame_idx for m in animal.measurements] == [7]
    assert not commands.measure_frame()        # that frame is measured: it is selected
    model.select(0, 0)
    commands.edit_animal()
    assert model.project.clips[0].animals[0].animal_id == "Tursiops A"
    commands.add_animal()
    assert len(model.project.clips[0].animals) == 2 and model.animal_idx == 1
    commands.remove_animal()
    assert [a.animal_id for a in model.project.clips[0].animals] == ["Tursiops A"]
    for _ in range(3):
        model.undo_stack.undo()
    assert model.project.clips[0].animals[0].animal_id != "Tursiops A"
