"""The Clip and Measure menus' commands on the tree of animals and measured frames: add, edit
and remove an animal, start a measurement on the frame shown, remove one. Each asks through
``Questions`` where it must, then pushes one undoable edit."""

from dataclasses import replace

from PySide6.QtCore import QObject

from dolphinfit.core.project.model import (
    Animal,
    Measurement,
    add_animal,
    add_measurement,
    next_animal_id,
    remove_animal,
    remove_measurement,
    with_animal,
)
from dolphinfit.core.project.scan_store import scan_animal, scan_animal_id
from dolphinfit.ui.dialogs.questions import Questions
from dolphinfit.ui.state.commands import push_edit
from dolphinfit.ui.state.project_model import Change, ProjectModel
from dolphinfit.ui.state.viewer_state import Notifier, ViewerState, selected_clip


class AnimalCommands(QObject):
    """Edits of the selected clip's animals and measured frames (module doc)."""

    def __init__(self, model: ProjectModel, state: ViewerState, ask: Questions,
                 notifier: Notifier, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.model, self.state, self.ask, self.notifier = model, state, ask, notifier

    def add_animal(self) -> None:
        clip_idx = selected_clip(self.model, self.notifier)
        if clip_idx is None:
            return
        clip = self.model.project.clips[clip_idx]
        push_edit(self.model, add_animal(self.model.project, clip_idx,
                                         Animal(next_animal_id(clip))),
                  "add animal", Change("structure"))
        self.model.select(clip_idx, len(clip.animals))

    def select_scan_animal(self, clip_idx: int, number: int) -> None:
        """Select the project animal of scan animal ``number`` ("dolphin N"), added first
        (undoable) when the clip has none of that name."""
        clip = self.model.project.clips[clip_idx]
        animal_idx = scan_animal(clip, number)
        if animal_idx is None:
            push_edit(self.model, add_animal(self.model.project, clip_idx,
                                             Animal(scan_animal_id(number))),
                      "add animal", Change("structure"))
            animal_idx = len(clip.animals)
        self.model.select(clip_idx, animal_idx)

    def edit_animal(self) -> None:
        m = self.model
        if m.animal_idx is None:
            self.notifier.error("No animal", "select an animal first")
            return
        clip = m.project.clips[m.clip_idx]
        animal = clip.animals[m.animal_idx]
        others = [a.animal_id for i, a in enumerate(clip.animals) if i != m.animal_idx]
        answer = self.ask.animal(animal, others)
        if answer is not None:
            animal_id, notes = answer
            push_edit(m, with_animal(m.project, m.clip_idx, m.animal_idx, replace(
                animal, animal_id=animal_id, notes=notes)),
                "edit animal", Change("structure"))

    def remove_animal(self) -> None:
        m = self.model
        if m.animal_idx is None:
            return
        animal = m.project.clips[m.clip_idx].animals[m.animal_idx]
        if self.ask.remove_animal(animal):
            push_edit(m, remove_animal(m.project, m.clip_idx, m.animal_idx),
                      f"remove {animal.animal_id}", Change("structure"))

    def measure_frame(self) -> bool:
        """Start a measurement of the selected animal (the clip's first, or a new one) on the
        frame shown, or select the one there; True when one was started."""
        m = self.model
        clip_idx = selected_clip(m, self.notifier)
        if clip_idx is None or self.state.session is None:
            return False
        project, animal_idx, frame_idx = m.project, m.animal_idx, self.state.frame_idx
        clip = project.clips[clip_idx]
        if animal_idx is None and clip.animals:
            animal_idx = 0  # the clip's first animal, until the user picks another
        elif animal_idx is None:
            project = add_animal(project, clip_idx, Animal(next_animal_id(clip)))
            animal_idx = 0
        existing = project.clips[clip_idx].animals[animal_idx].measurement_at(frame_idx)
        if existing is not None:
            m.select(clip_idx, animal_idx, existing)
            return False
        project, key = add_measurement(project, clip_idx, animal_idx, Measurement(frame_idx))
        push_edit(m, project, f"measure frame {frame_idx}", Change("structure", key=key))
        return True

    def remove_measurement(self) -> None:
        key = self.model.current_key()
        if key is not None:
            push_edit(self.model, remove_measurement(self.model.project, key),
                      "remove measured frame", Change("structure"))
