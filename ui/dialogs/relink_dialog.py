"""Find a clip's media that moved: pick a same-name file found under the project's folder,
browse for it, or skip and keep the clip unlinked."""

from collections.abc import Sequence
from pathlib import Path

from PySide6.QtCore import Qt
from PySide6.QtWidgets import (QDialog, QDialogButtonBox, QFileDialog, QLabel, QListWidget,
                               QListWidgetItem, QMenu, QVBoxLayout, QWidget)

PATH_ROLE = Qt.ItemDataRole.UserRole


class RelinkDialog(QDialog):
    """Where is the media now? ``chosen`` is the path picked (None when skipped)."""

    def __init__(self, stored_path: str | Path, project_dir: Path, candidates: Sequence[Path],
                 parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self._project_dir = Path(project_dir)
        self._name = Path(stored_path).name
        self.setWindowTitle(f"Relink {self._name}")
        expected = (self._project_dir / stored_path).resolve()
        found = (f"Same-name files under {self._project_dir}:" if candidates
                 else f"No file called {self._name} under {self._project_dir}: browse for it.")
        intro = QLabel(f"{self._name} was not found at {expected}.\nChoose where it is now, or "
                       f"skip to keep the clip unlinked (its measurements stay in the project)."
                       f"\n\n{found}", wordWrap=True)
        self._list = QListWidget(objectName="candidates")
        self._list.itemDoubleClicked.connect(self.accept)
        buttons = QDialogButtonBox()
        self._relink = buttons.addButton("Relink", QDialogButtonBox.ButtonRole.AcceptRole)
        browse = buttons.addButton("Browse…", QDialogButtonBox.ButtonRole.ActionRole)
        browse.setObjectName("browse")
        menu = QMenu(browse)
        menu.addAction("File…", self._browse_file)
        menu.addAction("Folder of frames…", self._browse_folder)
        browse.setMenu(menu)
        buttons.addButton("Skip", QDialogButtonBox.ButtonRole.RejectRole)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        self._list.currentItemChanged.connect(
            lambda item, _previous: self._relink.setEnabled(item is not None))
        self._relink.setEnabled(False)
        for path in candidates:
            self._add(Path(path))
        self._list.setCurrentRow(0)
        layout = QVBoxLayout(self)
        for widget in (intro, self._list, buttons):
            layout.addWidget(widget)

    def _add(self, path: Path) -> QListWidgetItem:
        item = QListWidgetItem(str(path), self._list)
        item.setData(PATH_ROLE, path)
        return item

    def _browsed(self, name: str) -> None:
        if name:
            self._list.setCurrentItem(self._add(Path(name)))

    def _browse_file(self) -> None:
        self._browsed(QFileDialog.getOpenFileName(self, f"Where is {self._name}?",
                                                  str(self._project_dir))[0])

    def _browse_folder(self) -> None:
        self._browsed(QFileDialog.getExistingDirectory(self, f"Where is {self._name}?",
                                                       str(self._project_dir)))

    def accept(self) -> None:
        if self._list.currentItem() is not None:
            super().accept()

    @property
    def chosen(self) -> Path | None:
        """The media's new path once accepted; None when skipped or cancelled."""
        item = self._list.currentItem()
        if self.result() != QDialog.DialogCode.Accepted or item is None:
            return None
        return item.data(PATH_ROLE)
