"""The open project as a Qt model: the immutable project tree, the current selection, the undo
stack and the autosave. Views connect to its signals and never poll; every change goes through
an undoable :class:`ProjectEdit` (ui/state/commands.py)."""

from dataclasses import dataclass
from pathlib import Path

from PySide6.QtCore import QObject, QTimer, Signal
from PySide6.QtGui import QUndoStack

from dolphinfit.core.project.model import Measurement, MeasurementKey, Project, get_measurement
from dolphinfit.core.project.project_file import autosave_path, write_project

AUTOSAVE_DELAY_MS = 1500  # after the last change; a burst of drags writes once
Selection = tuple[int | None, int | None, int | None]  # clip, animal, measured frame


@dataclass(frozen=True)
class Change:
    """What an edit touched: ``kind`` is "measurement" (with ``key``), "clip" (with ``clip``:
    its calibration or animals), "structure" (clips, animals or measurements added or removed)
    or "settings" (HW ratios, tail option)."""

    kind: str
    key: MeasurementKey | None = None
    clip: int | None = None


class ProjectModel(QObject):
    """Holds the project; emits ``changed(Change)`` after every edit, undo and redo."""

    changed = Signal(object)           # Change
    selection_changed = Signal()
    path_changed = Signal()
    replaced = Signal()                # another project is held (opened or new), not a Save As
    dirty_changed = Signal(bool)
    autosaved = Signal(str)            # the autosave file written
    autosave_failed = Signal(str)      # why

    def __init__(self, project: Project | None = None, path: Path | None = None,
                 parent: QObject | None = None) -> None:
        super().__init__(parent)
        self._project = project or Project()
        self._path = path
        self.clip_idx: int | None = None
        self.animal_idx: int | None = None
        self.measurement_idx: int | None = None
        self.undo_stack = QUndoStack(self)
        self.undo_stack.cleanChanged.connect(self._on_clean_changed)
        self._autosave = QTimer(self, singleShot=True, interval=AUTOSAVE_DELAY_MS)
        self._autosave.timeout.connect(self.write_autosave)
        self.select_first()

    def _on_clean_changed(self, clean: bool) -> None:
        self.dirty_changed.emit(not clean)

    # ----- state
    @property
    def project(self) -> Project:
        return self._project

    @property
    def path(self) -> Path | None:
        return self._path

    def reset(self, project: Project, path: Path | None) -> None:
        """Hold another project (opening a file): empty undo history, clean state."""
        self._autosave.stop()
        self.undo_stack.clear()
        self._project = project
        self._path = path
        self.clip_idx = self.animal_idx = self.measurement_idx = None
        self.replaced.emit()
        self.path_changed.emit()
        self.changed.emit(Change("structure"))
        self.select_first()
        self.selection_changed.emit()

    def set_path(self, path: Path | None) -> None:
        self._path = path
        self.path_changed.emit()

    @property
    def is_dirty(self) -> bool:
        return not self.undo_stack.isClean()

    def mark_saved(self) -> None:
        """The project was written: clean state, no autosave to offer."""
        self.undo_stack.setClean()
        self._autosave.stop()
        if self._path is not None:
            autosave_path(self._path).unlink(missing_ok=True)

    def selection(self) -> Selection:
        """The current (clip, animal, measured frame) indices."""
        return self.clip_idx, self.animal_idx, self.measurement_idx

    def set_state(self, project: Project, change: Change,
                  selection: Selection | None = None) -> None:
        """Replace the tree (commands only), select ``selection`` (else the edited
        measurement, else what is still valid of the current one) and tell the views."""
        before = self.selection()
        self._project = project
        if selection is None and change.key is not None:
            selection = (change.key.clip, change.key.animal, change.key.measurement)
        if selection is not None:
            self.clip_idx, self.animal_idx, self.measurement_idx = selection
        self._clamp_selection()
        self.changed.emit(change)
        if self.selection() != before:
            self.selection_changed.emit()
        self._autosave.start()

    # ----- selection
    def select(self, clip: int | None, animal: int | None = None,
               measurement: int | None = None) -> None:
        """Make a clip, animal and measured frame current (None for none)."""
        new = (clip, animal, measurement)
        if new != (self.clip_idx, self.animal_idx, self.measurement_idx):
            self.clip_idx, self.animal_idx, self.measurement_idx = new
            self._clamp_selection()
            self.selection_changed.emit()

    def select_first(self) -> None:
        """The first clip, its first animal and that animal's first measured frame."""
        clips = self._project.clips
        if not clips:
            self.select(None)
            return
        animals = clips[0].animals
        self.select(0, 0 if animals else None,
                    0 if animals and animals[0].measurements else None)

    def _clamp_selection(self) -> None:
        clips = self._project.clips
        if self.clip_idx is None or self.clip_idx >= len(clips):
            self.clip_idx = 0 if clips else None
            self.animal_idx = self.measurement_idx = None
        if self.clip_idx is None:
            return
        animals = clips[self.clip_idx].animals
        if self.animal_idx is not None and self.animal_idx >= len(animals):
            self.animal_idx = len(animals) - 1 if animals else None
        if self.animal_idx is None:
            self.measurement_idx = None
            return
        measurements = animals[self.animal_idx].measurements
        if self.measurement_idx is not None and self.measurement_idx >= len(measurements):
            self.measurement_idx = len(measurements) - 1 if measurements else None

    def current_key(self) -> MeasurementKey | None:
        """Key of the current measured frame, if any."""
        if None in (self.clip_idx, self.animal_idx, self.measurement_idx):
            return None
        return MeasurementKey(self.clip_idx, self.animal_idx, self.measurement_idx)

    def current_measurement(self) -> Measurement | None:
        key = self.current_key()
        return None if key is None else get_measurement(self._project, key)

    # ----- autosave
    def write_autosave(self) -> None:
        """Write the unsaved state beside the project file; back at the saved state (undo),
        remove it, so that no undone work is offered after a crash."""
        if self._path is None:
            return
        target = autosave_path(self._path)
        if not self.is_dirty:
            target.unlink(missing_ok=True)
            return
        try:
            write_project(target, self._project)
        except OSError as exc:
            self.autosave_failed.emit(f"{target}: {exc.strerror or exc}")
            return
        self.autosaved.emit(str(target))
