"""File → Export: which frames, animals or fits to export, asked through the window's
questions (ui.dialogs.questions); the writing on the export worker, off the GUI thread, with a
cancellable progress dialog; the outcome in the notifier (status line, or an error naming
what was not exported)."""

import threading
from collections.abc import Callable
from pathlib import Path

from PySide6.QtCore import QObject
from PySide6.QtWidgets import QWidget

from dolphinfit.core.fit.result import FitResult
from dolphinfit.core.progress import ProgressCallback
from dolphinfit.core.project.comparison import project_comparison_rows, write_comparison_csv
from dolphinfit.core.project.evaluate import all_keys
from dolphinfit.core.project.model import MeasurementKey, get_measurement
from dolphinfit.core.project.results import image_id
from dolphinfit.ui.dialogs.job_progress import JobProgress
from dolphinfit.ui.dialogs.questions import Questions
from dolphinfit.ui.state.project_model import ProjectModel
from dolphinfit.ui.state.viewer_state import Notifier
from dolphinfit.ui.workers.export_worker import ExportWorker
from dolphinfit.ui.workers.job_worker import Job

STATUS_MS = 10_000


class ExportController(QObject):
    """The export commands of the window over ``parent`` (module doc); ``shown_fit``: the
    current animal's 3D fit, or None."""

    def __init__(self, model: ProjectModel, notifier: Notifier, ask: Questions,
                 shown_fit: Callable[[], FitResult | None], parent: QWidget) -> None:
        super().__init__(parent)
        self.model, self.notifier, self.ask, self.shown_fit = model, notifier, ask, shown_fit
        self.worker = ExportWorker(self)
        self.last_export: list[Path] = []
        self._progress = JobProgress(self.worker, "Export", "Measuring and writing…", parent)
        self.worker.finished.connect(self._on_finished)
        self.worker.failed.connect(self._on_failed)
        self.worker.cancelled.connect(self._on_cancelled)

    def shutdown(self) -> None:
        self.worker.shutdown()

    # ------------------------------------------------------------------ commands
    def export_frame(self) -> None:
        """The selected measured frame."""
        key = self.model.current_key()
        if key is None:
            self.notifier.error("Export", "no measured frame is selected")
            return
        clip = self.model.project.clips[key.clip]
        self._export_frames([key], image_id(clip, get_measurement(self.model.project,
                                                                  key).frame_idx))

    def export_animal(self) -> None:
        """Every measured frame of the selected animal."""
        m = self.model
        if m.animal_idx is None:
            self.notifier.error("Export", "no animal is selected")
            return
        clip = m.project.clips[m.clip_idx]
        animal_id = clip.animals[m.animal_idx].animal_id
        self._export_frames(all_keys(m.project, m.clip_idx, m.animal_idx),
                            f"{Path(clip.media_path).stem}_{animal_id}".replace(" ", "-"))

    def export_project(self) -> None:
        """Every measured frame of the project."""
        path = self.model.path
        self._export_frames(all_keys(self.model.project), path.stem if path else "project")

    def export_comparison(self) -> None:
        """One row per animal with a 3D fit: both methods' figures and their difference."""
        if self.model.path is None:
            self.notifier.error("Export", "open a project first")
            return
        if self._busy():
            return
        target = self.ask.comparison_path(
            self.model.path.with_name(self.model.path.stem + "_comparison.csv"))
        if target is None:
            return
        project, path, draws = self.model.project, self.model.path, self.worker.num_draws

        def job(progress: ProgressCallback, cancel: threading.Event) -> tuple[list, list]:
            rows, notes = project_comparison_rows(project, path, draws, progress, cancel)
            write_comparison_csv(target, rows)
            return [target], notes

        self._run(job)

    def export_meshes(self) -> None:
        """The current animal's fitted meshes: rest pose and every fitted frame."""
        fit = self.shown_fit()
        if fit is None:
            self.notifier.error("Export", "this animal has no 3D fit")
            return
        if self._busy():
            return
        choice = self.ask.mesh_export(self._start_dir())
        if choice is None:
            return
        folder, suffix = choice

        def job(progress: ProgressCallback, cancel: threading.Event) -> tuple[list, list]:
            from dolphinfit.core.fit.mesh_files import export_fit_meshes  # trimesh, in the worker
            from dolphinfit.core.model.template import load_template
            return export_fit_meshes(fit, load_template(), folder, suffix, progress, cancel), []

        self._run(job)

    # ------------------------------------------------------------------ doing
    def _busy(self) -> bool:
        if self.worker.is_running:
            self.notifier.error("Export", "an export is already running")
        return self.worker.is_running

    def _start_dir(self) -> Path:
        """Where the export dialogs start: the project's folder."""
        return self.model.path.parent if self.model.path else Path.cwd()

    def _export_frames(self, keys: list[MeasurementKey], stem: str) -> None:
        """Measured frames, in all four formats, into a folder the user picks."""
        if self.model.path is None or not keys:
            self.notifier.error("Export", "nothing measured to export yet")
            return
        if self._busy():
            return
        out_dir = self.ask.export_dir(self._start_dir())
        if out_dir is not None and self.worker.start(self.model.project, self.model.path, keys,
                                                     out_dir, stem):
            self._progress.start()

    def _run(self, job: Job) -> None:
        if self.worker.run_job(job):
            self._progress.start()

    def _on_failed(self, why: str) -> None:
        self.notifier.error("Export failed", why)

    def _on_cancelled(self) -> None:
        self.notifier.status("export cancelled: nothing written", STATUS_MS)

    def _on_finished(self, outcome: tuple[list, list]) -> None:
        paths, skipped = outcome
        self.last_export = list(paths)
        text = f"wrote {len(paths)} file{'s' if len(paths) != 1 else ''}"
        if paths:
            text += f" into {Path(paths[0]).parent}"
        if skipped:
            self.notifier.error("Export", text + "\n\nnot exported:\n" + "\n".join(skipped))
        self.notifier.status(text, STATUS_MS)
