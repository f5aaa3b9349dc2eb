"""The take-off point's height above the water, asked with no value filled in: a prefilled
0.00 was taken as an answer by users who pressed Enter, and every altitude of those clips
came out short by the height of the boat's deck."""

from PySide6.QtWidgets import (QDialog, QDialogButtonBox, QFormLayout, QLabel, QLineEdit,
                               QVBoxLayout, QWidget)

from dolphinfit.core.limits import LAUNCH_HEIGHT_M
from dolphinfit.ui.dialogs.dialog_buttons import ok_cancel_buttons
from dolphinfit.ui.dialogs.message_label import MessageLabel


class LaunchHeightDialog(QDialog):
    """Ask the launch height (m) for ``clip_names``; OK only once a plausible number is
    typed (core.limits.LAUNCH_HEIGHT_M)."""

    def __init__(self, clip_names: list[str], parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Launch height")
        names = ", ".join(clip_names[:5]) + (" …" if len(clip_names) > 5 else "")
        count = len(clip_names)
        question = QLabel(
            f"{count} clip{'s' if count != 1 else ''} ({names}) record the height above the "
            "take-off point.\nHow high was the take-off point above the water? Clip → "
            "Altitude… changes it per clip.")
        question.setWordWrap(True)
        self._edit = QLineEdit(objectName="launch_height")
        self._edit.setPlaceholderText("e.g. 1.5 for a boat's deck")
        self._error = MessageLabel(objectName="error")
        buttons = ok_cancel_buttons(self)
        self._ok = buttons.button(QDialogButtonBox.StandardButton.Ok)
        form = QFormLayout()
        form.addRow("Launch height (m):", self._edit)
        layout = QVBoxLayout(self)
        layout.addWidget(question)
        layout.addLayout(form)
        layout.addWidget(self._error)
        layout.addWidget(buttons)
        self._edit.textChanged.connect(self._validate)
        self._validate()

    @property
    def launch_height_m(self) -> float | None:
        """The height typed (a decimal comma allowed), None unless a plausible number."""
        try:
            value = float(self._edit.text().strip().replace(",", "."))
        except ValueError:
            return None
        return value if LAUNCH_HEIGHT_M.low <= value <= LAUNCH_HEIGHT_M.high else None

    def _validate(self) -> None:
        text = self._edit.text().strip()
        problem = "" if self.launch_height_m is not None else (
            "Type the height in metres (0 if you took off from the water)." if not text else
            f"{text!r} is not a launch height of {LAUNCH_HEIGHT_M.text()}.")
        self._error.show_message(problem, "error" if text else "info")
        self._ok.setEnabled(not problem)

    def accept(self) -> None:
        if self.launch_height_m is not None:
            super().accept()
