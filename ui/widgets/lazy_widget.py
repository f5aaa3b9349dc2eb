"""A dock's content built the first time it is shown: the 3D view (VTK) and the comparison
plot (matplotlib) take about a second to import, which the app should not spend opening."""

from collections.abc import Callable

from PySide6.QtCore import Signal
from PySide6.QtGui import QShowEvent
from PySide6.QtWidgets import QLabel, QVBoxLayout, QWidget


class LazyWidget(QWidget):
    """Holds a placeholder until first shown, then the widget ``factory`` makes (``built``
    is emitted once with it)."""

    built = Signal(object)

    def __init__(self, factory: Callable[[], QWidget], placeholder: str,
                 parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._factory = factory
        self.widget: QWidget | None = None
        self._layout = QVBoxLayout(self)
        self._layout.setContentsMargins(0, 0, 0, 0)
        self._placeholder = QLabel(placeholder, wordWrap=True)
        self._layout.addWidget(self._placeholder)

    def showEvent(self, event: QShowEvent) -> None:  # noqa: N802 (Qt's name)
        super().showEvent(event)
        if self.widget is None:
            self.widget = self._factory()
            self._placeholder.deleteLater()
            self._layout.addWidget(self.widget)
            self.built.emit(self.widget)
