"""File → Add clips: several videos, or a folder of them, checked in a worker with a progress
dialog (core.project.clip_intake), then added in one undoable step; the launch height asked
once for the clips whose SRT records height above take-off; what was put aside, and the
camera guesses to check, reported in one dialog. Without an open project, the project beside
the first video (or the folder) is opened or started first."""

import threading
from pathlib import Path

from PySide6.QtCore import QObject, Signal
from PySide6.QtWidgets import QWidget

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.media import video_files
from dolphinfit.core.progress import ProgressCallback
from dolphinfit.core.project.clip_intake import Intake, intake, with_launch_height
from dolphinfit.core.project.model import add_clip
from dolphinfit.ui.controllers.project_files import ProjectFiles
from dolphinfit.ui.dialogs.job_progress import JobProgress
from dolphinfit.ui.dialogs.questions import Questions
from dolphinfit.ui.state.commands import push_edit
from dolphinfit.ui.state.project_model import Change, ProjectModel
from dolphinfit.ui.state.viewer_state import Notifier
from dolphinfit.ui.workers.job_worker import JobWorker

STATUS_MS = 10_000


class ClipIntakeController(QObject):
    """Adds many clips at once (module doc); ``clip_chosen`` once the first is selected."""

    clip_chosen = Signal()

    def __init__(self, model: ProjectModel, files: ProjectFiles, ask: Questions,
                 notifier: Notifier, dialog_parent: QWidget) -> None:
        super().__init__(dialog_parent)
        self.model, self.files, self.ask, self.notifier = model, files, ask, notifier
        self.worker = JobWorker(self)
        self._progress = JobProgress(self.worker, "Add clips", "Reading the clips…",
                                     dialog_parent)
        self.worker.finished.connect(self._on_checked)
        self.worker.failed.connect(lambda why: notifier.error("Add clips", why))
        self.worker.cancelled.connect(
            lambda: notifier.status("adding clips cancelled: nothing added", STATUS_MS))

    def add(self, paths: list[Path]) -> None:
        """Add the videos ``paths`` (a folder: the videos in it)."""
        try:
            videos = [video for path in paths for video in video_files(path)]
        except InputError as exc:
            self.notifier.error("Add clips", str(exc))
            return
        if not videos or self.worker.is_running:
            return
        if self.model.path is None and not self.files.open_project_for(
                paths[0] if len(paths) == 1 and paths[0].is_dir() else videos[0]):
            return
        project_path = self.model.path
        known = {clip.media_path for clip in self.model.project.clips}

        def job(progress: ProgressCallback, cancel: threading.Event) -> tuple[Path, Intake]:
            return project_path, intake(videos, project_path.parent, known, progress, cancel)

        if self.worker.run_job(job):
            self._progress.start()

    def _on_checked(self, outcome: tuple[Path, Intake]) -> None:
        project_path, found = outcome
        if project_path != self.model.path:  # their paths are relative to that project
            self.notifier.error("Add clips", "the clips were not added: another project is "
                                "open now")
            return
        relative = [clip.entry.name for clip in found.clips if clip.relative_altitude]
        launch_m = 0.0
        if relative:
            launch_m = self.ask.launch_height(relative)
            if launch_m is None:
                self.notifier.status("adding clips cancelled: nothing added", STATUS_MS)
                return
        project, first = self.model.project, len(self.model.project.clips)
        for clip in found.clips:
            project = add_clip(project, with_launch_height(clip, launch_m))
        if found.clips:
            count = len(found.clips)
            push_edit(self.model, project, f"add {count} clip{'s' if count != 1 else ''}",
                      Change("structure"))
            self.model.select(first)
            self.clip_chosen.emit()
        unsure = [f"{clip.entry.name}: {clip.camera.why}" for clip in found.clips
                  if not clip.camera.sure]
        text = f"{len(found.clips)} clip{'s' if len(found.clips) != 1 else ''} added."
        if found.refused:
            text += (f"\n\n{len(found.refused)} put aside:\n" + "\n".join(found.refused[:8])
                     + ("\n…" if len(found.refused) > 8 else ""))
        if unsure:
            text += "\n\nCamera to check:\n" + "\n".join(unsure[:8])
        self.ask.report("Add clips", text, [*found.refused, *unsure])

    def shutdown(self) -> None:
        self.worker.shutdown()
