"""The project tree: clips with where each stands (altitude, scanned, animals found, frames
measured, animals fitted; core.project.scan_store.ClipStatus), their animals and each
animal's measured frames with its length and volume; selecting a row makes it current (and
jumps to that frame). Several rows are selected with Ctrl or Shift (their clips take one
camera together: Clip → Camera…). A clip that still needs work is shown in bold."""

from PySide6.QtCore import QItemSelectionModel, Qt
from PySide6.QtGui import QFont
from PySide6.QtWidgets import (QAbstractItemView, QHeaderView, QTreeWidget, QTreeWidgetItem,
                               QVBoxLayout, QWidget)

from dolphinfit.core.project.model import MeasurementKey
from dolphinfit.core.project.scan_store import ClipStatus
from dolphinfit.ui.state.project_model import Change, ProjectModel

ROLE_PATH = Qt.ItemDataRole.UserRole  # (clip, animal or None, measurement or None)
INDENT_CHARS = 2   # a level's indentation: narrower than Qt's, it leaves the names room


class ProjectPanel(QWidget):
    """Observes the model: rebuilds on structure changes, follows the selection."""

    def __init__(self, model: ProjectModel, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._model = model
        self._figures: dict[MeasurementKey, str] = {}
        self._statuses: list[ClipStatus] = []
        self.tree = QTreeWidget()
        self.tree.setHeaderLabels(["clip / animal / frame", "status / length, volume"])
        header = self.tree.header()   # the statuses whole; the names give way, their ends shown
        header.setStretchLastSection(False)
        header.setSectionResizeMode(0, QHeaderView.ResizeMode.Stretch)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.ResizeToContents)
        self.tree.setTextElideMode(Qt.TextElideMode.ElideMiddle)
        self.tree.setIndentation(self.tree.fontMetrics().averageCharWidth() * INDENT_CHARS)
        self.tree.setSelectionMode(QAbstractItemView.SelectionMode.ExtendedSelection)
        self.tree.itemSelectionChanged.connect(self._on_tree_selection)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.addWidget(self.tree)
        model.changed.connect(self._on_changed)
        model.selection_changed.connect(self._follow_selection)
        self._rebuild()

    def set_figures(self, figures: dict[MeasurementKey, str]) -> None:
        """Length and volume text of measured frames (from the results worker)."""
        self._figures.update(figures)
        for item in self._items():
            path = item.data(0, ROLE_PATH)
            if path[2] is not None:
                item.setText(1, self._figures.get(MeasurementKey(*path), ""))

    def set_statuses(self, statuses: list[ClipStatus]) -> None:
        """Every clip's status, in clip order (from the scan controller)."""
        self._statuses = list(statuses)
        for c in range(self.tree.topLevelItemCount()):
            self._show_status(self.tree.topLevelItem(c), c)

    def _show_status(self, item: QTreeWidgetItem, clip_idx: int) -> None:
        clip = self._model.project.clips[clip_idx]
        if clip_idx < len(self._statuses):
            status = self._statuses[clip_idx]
            text, bold = status.text(), status.needs_work
        else:
            text = f"{clip.kind}, {'altitude set' if clip.altitude else 'no altitude'}"
            bold = False
        item.setText(1, text)
        font = QFont(item.font(0))
        font.setBold(bold)
        item.setFont(0, font)
        item.setToolTip(1, "needs work (View → Next clip that needs work, Ctrl+J)" if bold
                        else text)

    def _on_changed(self, change: Change) -> None:
        if change.kind in ("structure", "clip"):
            self._figures.clear()
            self._rebuild()

    def _rebuild(self) -> None:
        self.tree.blockSignals(True)
        self.tree.clear()
        for c, clip in enumerate(self._model.project.clips):
            clip_item = QTreeWidgetItem([clip.name, ""])
            clip_item.setData(0, ROLE_PATH, (c, None, None))
            clip_item.setToolTip(0, clip.media_path)
            self.tree.addTopLevelItem(clip_item)
            self._show_status(clip_item, c)
            for a, animal in enumerate(clip.animals):
                n = len(animal.measurements)
                animal_item = QTreeWidgetItem([animal.animal_id,
                                               f"{n} frame{'s' if n != 1 else ''}"])
                animal_item.setData(0, ROLE_PATH, (c, a, None))
                animal_item.setToolTip(0, animal.notes or "no notes")
                clip_item.addChild(animal_item)
                for m, measurement in enumerate(animal.measurements):
                    frame_item = QTreeWidgetItem([
                        f"frame {measurement.frame_idx}",
                        self._figures.get(MeasurementKey(c, a, m), "")])
                    frame_item.setData(0, ROLE_PATH, (c, a, m))
                    animal_item.addChild(frame_item)
        self.tree.expandAll()
        self.tree.blockSignals(False)
        self._follow_selection()

    def _items(self) -> list[QTreeWidgetItem]:
        found, stack = [], [self.tree.topLevelItem(i) for i in range(self.tree.topLevelItemCount())]
        while stack:
            item = stack.pop()
            found.append(item)
            stack += [item.child(i) for i in range(item.childCount())]
        return found

    def selected_clips(self) -> list[int]:
        """The clips of the selected rows, in order."""
        return sorted({item.data(0, ROLE_PATH)[0] for item in self.tree.selectedItems()})

    def _follow_selection(self) -> None:
        """Make the model's current row current and the only one selected; the row clicked
        last is already current, and the rows selected with it stay selected."""
        m = self._model
        wanted = (m.clip_idx, m.animal_idx, m.measurement_idx)
        for item in self._items():
            if item.data(0, ROLE_PATH) == wanted:
                if item is not self.tree.currentItem():
                    self.tree.blockSignals(True)
                    self.tree.setCurrentItem(item, 0,
                                             QItemSelectionModel.SelectionFlag.ClearAndSelect)
                    self.tree.blockSignals(False)
                return

    def _on_tree_selection(self) -> None:
        item = self.tree.currentItem()
        if item is not None:
            clip, animal, measurement = item.data(0, ROLE_PATH)
            if animal is not None and measurement is None:
                measurements = self._model.project.clips[clip].animals[animal].measurements
                measurement = 0 if measurements else None
            self._model.select(clip, animal, measurement)
