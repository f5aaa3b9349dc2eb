"""Undoable edits: every user action that changes the project is one :class:`ProjectEdit`.

A command holds the project tree before and after (immutable values that share unchanged
branches), so undo and redo only swap trees; undo also restores what was selected before.
Consecutive edits with the same ``merge_tag`` (one drag of one handle) merge into one undo
step.
"""

from collections.abc import Hashable

from PySide6.QtGui import QUndoCommand

from dolphinfit.core.project.model import Measurement, MeasurementKey, Project, with_measurement
from dolphinfit.ui.state.project_model import Change, ProjectModel

MERGE_ID = 1


class ProjectEdit(QUndoCommand):
    """Replace the project tree; undo puts the old one back."""

    def __init__(self, model: ProjectModel, after: Project, text: str, change: Change,
                 merge_tag: Hashable | None = None) -> None:
        super().__init__(text)
        self._model = model
        self._before = model.project
        self._selection_before = model.selection()
        self._after = after
        self._change = change
        self._merge_tag = merge_tag

    def id(self) -> int:  # noqa: A003 (Qt's name)
        return MERGE_ID if self._merge_tag is not None else -1

    def mergeWith(self, other: QUndoCommand) -> bool:  # noqa: N802 (Qt's name)
        if not isinstance(other, ProjectEdit) or other._merge_tag != self._merge_tag:
            return False
        self._after = other._after
        return True

    def redo(self) -> None:
        self._model.set_state(self._after, self._change)

    def undo(self) -> None:
        self._model.set_state(self._before, self._change, self._selection_before)


def push_edit(model: ProjectModel, after: Project, text: str, change: Change,
              merge_tag: Hashable | None = None) -> None:
    """Apply an edit through the undo stack."""
    model.undo_stack.push(ProjectEdit(model, after, text, change, merge_tag))


def edit_measurement(model: ProjectModel, key: MeasurementKey, measurement: Measurement,
                     text: str, merge_tag: Hashable | None = None) -> None:
    """Replace one measured frame through the undo stack."""
    push_edit(model, with_measurement(model.project, key, measurement), text,
              Change("measurement", key=key), merge_tag)
