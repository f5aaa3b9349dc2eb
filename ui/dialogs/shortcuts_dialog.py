"""Help → Keyboard shortcuts: every action of the action table by menu, and the mouse."""

from PySide6.QtGui import QKeySequence
from PySide6.QtWidgets import (QAbstractItemView, QDialog, QDialogButtonBox, QHeaderView,
                               QTableWidget, QTableWidgetItem, QVBoxLayout, QWidget)

from dolphinfit.ui.action_table import CTRL, MOUSE_GESTURES, load_action_table

COLUMNS = ("Menu", "Key", "Action")
MOUSE = "Mouse"


def native_key_text(shortcut: str) -> str:
    """``shortcut`` ("Ctrl+Shift+S") as the platform writes it ("⇧⌘S" on macOS)."""
    return QKeySequence(shortcut).toString(QKeySequence.SequenceFormat.NativeText)


def _ctrl_prefix() -> str:
    """How the platform writes Ctrl before a key ("Ctrl+", "⌘")."""
    return native_key_text("Ctrl+A").removesuffix("A")


class ShortcutsDialog(QDialog):
    """A read-only table: menu, key and action, in menu order, then the mouse gestures."""

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Keyboard shortcuts")
        menus, actions = load_action_table()
        rows = [(a.where, native_key_text(a.shortcut), a.label)
                for a in sorted(actions, key=lambda a: menus.index(a.menu))]
        rows += [(MOUSE, gesture.replace(CTRL, _ctrl_prefix()), what)
                 for gesture, what in MOUSE_GESTURES]
        table = QTableWidget(len(rows), len(COLUMNS), objectName="shortcuts")
        table.setHorizontalHeaderLabels(COLUMNS)
        for row, values in enumerate(rows):
            for column, text in enumerate(values):
                table.setItem(row, column, QTableWidgetItem(text))
        table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        table.verticalHeader().hide()
        table.resizeColumnsToContents()
        table.horizontalHeader().setSectionResizeMode(len(COLUMNS) - 1,
                                                      QHeaderView.ResizeMode.Stretch)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Close)
        buttons.rejected.connect(self.reject)
        layout = QVBoxLayout(self)
        layout.addWidget(table)
        layout.addWidget(buttons)
        self.resize(640, 720)
