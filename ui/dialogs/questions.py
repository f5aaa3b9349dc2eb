"""Every question the main window asks the user, apart from what the answers lead to (the
asking apart from the doing, as SLEAP's commands): each method opens one dialog and returns
the answer, or None (False, "cancel") when the user cancels. The window's handlers ask here,
then act; tests answer by replacing a method, with no dialog shown."""

from pathlib import Path

from PySide6.QtCore import QUrl
from PySide6.QtGui import QDesktopServices
from PySide6.QtWidgets import QFileDialog, QInputDialog, QMessageBox, QWidget

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.crash_report import installed_version
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.frame_source import Clip
from dolphinfit.core.io.media import MEDIA_SUFFIXES, VIDEO_SUFFIXES
from dolphinfit.core.project.model import AltitudeCalibrationSet, AltitudeSpec, Animal
from dolphinfit.core.project.project_file import PROJECT_SUFFIX, autosave_path, find_moved_media
from dolphinfit.core.resources import RESOURCES_DIR
from dolphinfit.core.segment.sam2_backend import check_checkpoint, config_for
from dolphinfit.ui.dialogs.altitude_dialog import AltitudeDialog
from dolphinfit.ui.dialogs.animal_dialog import AnimalDialog
from dolphinfit.ui.dialogs.calibration_dialog import CalibrationChoice, CalibrationDialog
from dolphinfit.ui.dialogs.camera_dialog import CameraAnswer, CameraDialog
from dolphinfit.ui.dialogs.handle_style_dialog import HandleStyleDialog
from dolphinfit.ui.dialogs.launch_height_dialog import LaunchHeightDialog
from dolphinfit.ui.dialogs.relink_dialog import RelinkDialog
from dolphinfit.ui.dialogs.shortcuts_dialog import ShortcutsDialog
from dolphinfit.ui.state.handle_style import HandleStyle

ABOUT = ("<p><b>dolphinfit {version}</b>: body length, volume, body condition and mass of "
         "dolphins from nadir drone video, by the elliptical baseline (Christiansen et al. "
         "2019) and a model-based 3D fit.</p><p>MIT licence.</p><p>If you use it, cite the "
         "method it implements: Baieri D., Cicciarella R., Krützen M., Rodolà E., Zuffi S. "
         "(2025) Model-based metric 3D shape and motion reconstruction of wild bottlenose "
         "dolphins in drone-shot videos. arXiv:2504.15782; and dolphinfit {version} itself "
         "(CITATION.cff in its repository).</p>")
# the manual as `make docs` builds it, shipped in the wheel with the other resources
MANUAL_INDEX = RESOURCES_DIR / "manual" / "index.html"


def version() -> str:
    """The installed dolphinfit's version ("unknown" outside an installed package)."""
    return installed_version("dolphinfit") or "unknown"


def _path(name: str) -> Path | None:
    return Path(name) if name else None


class Questions:
    """The dialogs of the main window (module doc); ``parent`` is the window."""

    def __init__(self, parent: QWidget) -> None:
        self.parent = parent

    # ------------------------------------------------------------------ telling
    def warn(self, title: str, text: str) -> None:
        """Something failed: a warning the user closes."""
        QMessageBox.warning(self.parent, title, text)

    def crash(self, report: Path | None, work: str) -> None:
        """Something in dolphinfit failed: where its report is, what became of the work."""
        where = (f"A crash report was written to {report}. Please attach it to a bug report "
                 f"and say what you were doing." if report is not None
                 else "The crash report could not be written (see the terminal).")
        QMessageBox.critical(self.parent, "dolphinfit: internal error",
                             f"Something in dolphinfit failed; the last action did not "
                             f"complete.\n\n{work}\n\n{where}")

    def show_shortcuts(self) -> None:
        ShortcutsDialog(self.parent).exec()

    def show_about(self) -> None:
        QMessageBox.about(self.parent, "About dolphinfit", ABOUT.format(version=version()))

    def show_manual(self) -> None:
        """The manual in the web browser, from the files on this machine; where it is not
        built, how to build it."""
        if MANUAL_INDEX.exists():
            QDesktopServices.openUrl(QUrl.fromLocalFile(str(MANUAL_INDEX)))
        else:
            self.warn("Manual", f"The manual is not built on this machine ({MANUAL_INDEX} "
                                f"is missing). In a clone of dolphinfit, `make docs` builds "
                                f"it; its pages are also readable as Markdown in the clone's "
                                f"docs/ folder.")

    # ------------------------------------------------------------------ files and folders
    def media_to_open(self) -> Path | None:
        """A project, clip or image to open."""
        suffixes = " ".join(f"*{s}" for s in sorted(MEDIA_SUFFIXES))
        name, _ = QFileDialog.getOpenFileName(
            self.parent, "Open project, clip or image", "",
            f"Projects and media (*{PROJECT_SUFFIX} {suffixes});;All files (*)")
        return _path(name)

    def media_to_add(self) -> Path | None:
        """A clip or image to add to the open project."""
        name, _ = QFileDialog.getOpenFileName(self.parent, "Add clip or image", "",
                                              " ".join(f"*{s}" for s in MEDIA_SUFFIXES))
        return _path(name)

    def videos_to_add(self) -> list[Path]:
        """Videos to add to the project at once (none when cancelled)."""
        names, _ = QFileDialog.getOpenFileNames(self.parent, "Add clips", "",
                                                " ".join(f"*{s}" for s in VIDEO_SUFFIXES))
        return [Path(name) for name in names]

    def frames_folder(self, title: str) -> Path | None:
        """A folder of numbered frames."""
        return _path(QFileDialog.getExistingDirectory(self.parent, title))

    def save_path(self, current: Path | None) -> Path | None:
        """Where to save the project, with the project suffix."""
        start = str(current or Path.cwd() / f"untitled{PROJECT_SUFFIX}")
        name, _ = QFileDialog.getSaveFileName(self.parent, "Save project as", start,
                                              f"dolphinfit projects (*{PROJECT_SUFFIX})")
        if not name:
            return None
        path = Path(name)
        return path if path.suffix == PROJECT_SUFFIX else path.with_name(path.name + PROJECT_SUFFIX)

    def export_dir(self, start: Path) -> Path | None:
        """A folder to export into."""
        return _path(QFileDialog.getExistingDirectory(self.parent, "Export into folder",
                                                      str(start)))

    def comparison_path(self, start: Path) -> Path | None:
        """The comparison CSV to write."""
        name, _ = QFileDialog.getSaveFileName(self.parent, "Export comparison", str(start),
                                              "CSV (*.csv)")
        return _path(name)

    def mesh_export(self, start: Path) -> tuple[Path, str] | None:
        """A mesh format, then a folder."""
        from dolphinfit.core.io.mesh_export import (  # trimesh: loaded when first needed
            MESH_SUFFIXES,
        )

        suffix, ok = QInputDialog.getItem(self.parent, "Export 3D fit meshes", "Format:",
                                          list(MESH_SUFFIXES), 0, False)
        if not ok:
            return None
        folder = self.export_dir(start)
        return None if folder is None else (folder, suffix)

    def masks_source(self) -> Path | None:
        """A folder of mask PNGs, else a mask file (.npz or a mask video)."""
        name = QFileDialog.getExistingDirectory(self.parent, "Folder of mask PNGs (%06d.png)")
        if not name:
            name, _ = QFileDialog.getOpenFileName(self.parent, "Mask file", "",
                                                  "Masks (*.npz *.mp4 *.avi *.mkv)")
        return _path(name)

    def lens_file(self) -> Path | None:
        """A lens model written by `dolphinfit calibrate lens`."""
        name, _ = QFileDialog.getOpenFileName(self.parent, "Lens model", "",
                                              "Lens models (*.json);;All files (*)")
        return _path(name)

    def sam2_checkpoint(self) -> Path | None:
        """A SAM-2 checkpoint whose model can be told (a warning and None otherwise)."""
        name, _ = QFileDialog.getOpenFileName(
            self.parent, "SAM-2 checkpoint (e.g. sam2.1_hiera_tiny.pt)", "",
            "SAM-2 checkpoint (*.pt)")
        if not name:
            return None
        try:
            config_for(check_checkpoint(name))
        except InputError as exc:
            self.warn("SAM-2 checkpoint", str(exc))
            return None
        return Path(name)

    def relink(self, stored: str, project_dir: Path) -> Path | None:
        """Where the moved media of a clip now is."""
        dialog = RelinkDialog(stored, project_dir,
                              find_moved_media(project_dir, Path(stored).name), self.parent)
        return dialog.chosen if dialog.exec() else None

    # ------------------------------------------------------------------ choices
    def restore_autosave(self, path: Path) -> bool:
        """Whether to restore the project's unsaved work."""
        answer = QMessageBox.question(
            self.parent, "Restore unsaved work?",
            f"{autosave_path(path).name} holds changes to {path.name} that were never saved "
            "(the app closed without saving). Restore them?")
        return answer == QMessageBox.Yes

    def media_changed(self, names: list[str]) -> bool:
        """Whether to take clips' media, changed on disk since they were added, as they are
        now (nothing is changed otherwise, and the question comes again at the next opening)."""
        shown = ", ".join(names[:5]) + (" …" if len(names) > 5 else "")
        answer = QMessageBox.question(
            self.parent, "Media changed on disk",
            f"{shown} {'has' if len(names) == 1 else 'have'} changed on disk since "
            f"{'it was' if len(names) == 1 else 'they were'} added to this project (the "
            "content is not the same). Frames measured, masks and 3D fits were made on the "
            "old file and may not match the new one.\n\nNothing has been changed. Take the "
            "files as they are now? (No: you are asked again when the project next opens.)")
        return answer == QMessageBox.Yes

    def save_changes(self) -> str:
        """"save", "discard" or "cancel" the open project's changes."""
        answer = QMessageBox.question(
            self.parent, "Unsaved changes", "Save the changes to this project before closing?",
            QMessageBox.Save | QMessageBox.Discard | QMessageBox.Cancel)
        return {QMessageBox.Save: "save", QMessageBox.Discard: "discard"}.get(answer, "cancel")

    def remove_animal(self, animal: Animal) -> bool:
        """Whether to remove the animal and its measured frames."""
        return QMessageBox.question(
            self.parent, "Remove animal", f"Remove {animal.animal_id} and its "
            f"{len(animal.measurements)} measured frames? (Undo brings them back.)"
        ) == QMessageBox.Yes

    def launch_height(self, clip_names: list[str]) -> float | None:
        """The take-off point's height above the water (m) for clips whose SRT records
        height above take-off."""
        dialog = LaunchHeightDialog(clip_names, self.parent)
        return dialog.launch_height_m if dialog.exec() else None

    def report(self, title: str, text: str, details: list[str]) -> None:
        """Something done, with a list the user may read (e.g. clips put aside and why)."""
        box = QMessageBox(QMessageBox.Icon.Information, title, text, QMessageBox.Ok,
                          self.parent)
        if details:
            box.setDetailedText("\n".join(details))
        box.exec()

    def frame_number(self, current: int, last: int) -> int | None:
        """A frame to go to, 0 … ``last``."""
        value, ok = QInputDialog.getInt(self.parent, "Go to frame", f"frame (0–{last}):",
                                        current, 0, last)
        return value if ok else None

    # ------------------------------------------------------------------ settings dialogs
    def altitude_calibration(self, current: AltitudeCalibrationSet | None,
                             clip_camera: CameraPreset, clip_preset: str | None,
                             clips: list[tuple[int, str, float]],
                             ticked: set[int]) -> CalibrationChoice | None:
        """A calibration (``current`` edited; a new one's camera chosen, the open clip's
        offered first) and the clips it corrects (CalibrationDialog)."""
        dialog = CalibrationDialog(current, clip_camera, clip_preset, clips, ticked,
                                   self.parent)
        return dialog.choice() if dialog.exec() else None

    def altitude(self, media: Path, project_dir: Path, clip: Clip,
                 current: AltitudeSpec | None) -> AltitudeSpec | None:
        """The clip's altitude (its SRT sidecar offered first)."""
        dialog = AltitudeDialog(media, project_dir, clip, current, self.parent)
        return dialog.spec if dialog.exec() else None

    def camera(self, camera: CameraPreset | None, preset_name: str | None, width_px: int,
               height_px: int, num_clips: int) -> CameraAnswer | None:
        """The camera of the open clip (``width_px`` × ``height_px``) and of the other clips
        selected with it (``num_clips`` in all)."""
        dialog = CameraDialog(camera, preset_name, width_px, height_px, self.parent, num_clips)
        return dialog.answer if dialog.exec() else None

    def animal(self, animal: Animal, others: list[str]) -> tuple[str, str] | None:
        """The animal's (id, notes); ``others``: the clip's other animals' ids."""
        dialog = AnimalDialog(animal.animal_id, animal.notes, others, self.parent)
        return (dialog.animal_id, dialog.notes) if dialog.exec() else None

    def handle_style(self, current: HandleStyle) -> HandleStyle | None:
        """How the measuring handles are drawn."""
        dialog = HandleStyleDialog(current, self.parent)
        return dialog.style if dialog.exec() else None
