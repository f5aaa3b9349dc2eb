"""An animal's ID and notes; the ID must be non-empty and unique within its clip."""

from collections.abc import Iterable

from PySide6.QtWidgets import (QDialog, QDialogButtonBox, QFormLayout, QLineEdit,
                               QPlainTextEdit, QVBoxLayout, QWidget)

from dolphinfit.ui.dialogs.dialog_buttons import ok_cancel_buttons
from dolphinfit.ui.dialogs.message_label import MessageLabel


class AnimalDialog(QDialog):
    """Edit ``animal_id`` and ``notes``; ``other_ids``: the clip's other animals.

    IDs are compared ignoring case and surrounding spaces: exports group rows by ID, and
    "Dolphin 1" next to "dolphin 1" would read as one animal.
    """

    def __init__(self, animal_id: str = "", notes: str = "", other_ids: Iterable[str] = (),
                 parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Animal")
        self._taken = {other.strip().casefold() for other in other_ids}
        self._id_edit = QLineEdit(animal_id, objectName="animal_id")
        self._notes_edit = QPlainTextEdit(notes, objectName="notes")
        self._error = MessageLabel(objectName="error")
        buttons = ok_cancel_buttons(self)
        self._ok = buttons.button(QDialogButtonBox.StandardButton.Ok)
        form = QFormLayout()
        form.addRow("Animal ID:", self._id_edit)
        form.addRow("Notes:", self._notes_edit)
        layout = QVBoxLayout(self)
        layout.addLayout(form)
        layout.addWidget(self._error)
        layout.addWidget(buttons)
        self._id_edit.textChanged.connect(self._validate)
        self._validate()

    def _problem(self) -> str:
        if not self.animal_id:
            return "The animal needs an ID."
        if self.animal_id.casefold() in self._taken:
            return f"Another animal of this clip is already called {self.animal_id!r}."
        return ""

    def _validate(self) -> None:
        problem = self._problem()
        self._error.show_message(problem, "error")
        self._ok.setEnabled(not problem)

    def accept(self) -> None:
        if not self._problem():
            super().accept()

    @property
    def animal_id(self) -> str:
        """The ID typed, without surrounding spaces."""
        return self._id_edit.text().strip()

    @property
    def notes(self) -> str:
        return self._notes_edit.toPlainText()
