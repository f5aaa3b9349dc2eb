"""A word-wrapped label for a dialog's inline message, coloured by level, hidden when empty."""

from PySide6.QtWidgets import QLabel, QWidget

LEVEL_COLOURS = {"info": "", "warning": "#b36b00", "error": "#d32f2f"}


class MessageLabel(QLabel):
    """Shows one message; ``level`` is its level ("info", "warning" or "error")."""

    def __init__(self, parent: QWidget | None = None, **qt_properties: object) -> None:
        super().__init__(parent, **qt_properties)
        self.setWordWrap(True)
        self.hide()
        self.level = "info"

    def show_message(self, text: str, level: str = "info") -> None:
        """Show ``text`` in the colour of ``level`` ("info", "warning" or "error")."""
        colour = LEVEL_COLOURS[level]
        self.level = level
        self.setStyleSheet(f"color: {colour}" if colour else "")
        self.setText(text)
        self.setVisible(bool(text))

    def clear_message(self) -> None:
        self.show_message("")
