"""Opening and saving: a project file, or media (a clip, an image, a folder of frames) that
opens the project beside it or starts one; the autosave offered back, moved media relinked,
unsaved work saved or discarded before another project opens, and the recent-projects list.
Questions go through the window's ``Questions``, failures to the notifier. The window closes
its clip session on ``session_closing`` and opens the model's current clip on
``clip_chosen``."""

from pathlib import Path

from PySide6.QtCore import QObject, Signal

from dolphinfit.core.errors import InputError
from dolphinfit.core.project.media_check import changed_media, with_media_accepted
from dolphinfit.core.project.model import ClipEntry, Project
from dolphinfit.core.project.new_project import clip_entry_for, project_path_for, project_with_clip
from dolphinfit.core.project.project_file import (
    PROJECT_SUFFIX,
    autosave_path,
    has_newer_autosave,
    missing_media,
    read_project,
    rebase_media,
    relink_clip,
    write_project,
)
from dolphinfit.core.project.recent import add_recent
from dolphinfit.ui.dialogs.questions import Questions
from dolphinfit.ui.state.commands import push_edit
from dolphinfit.ui.state.project_model import Change, ProjectModel
from dolphinfit.ui.state.viewer_state import Notifier
from dolphinfit.ui.workers.background import BackgroundJobs

STATUS_MS = 10_000


class ProjectFiles(QObject):
    """File → Open, Add, Save (module doc)."""

    session_closing = Signal()   # the open clip's session must close: the project changes
    clip_chosen = Signal()       # the model's current clip should be shown

    def __init__(self, model: ProjectModel, ask: Questions, notifier: Notifier,
                 jobs: BackgroundJobs, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.model, self.ask, self.notifier, self.jobs = model, ask, notifier, jobs
        self._media_jobs = BackgroundJobs(self)

    def open_path(self, path: Path) -> None:
        """Open a project file, or media (a clip, an image or a folder of frames)."""
        path = Path(path).expanduser().resolve()
        if not path.exists():
            self.notifier.error("Cannot open", f"{path}: no such file or folder")
            return
        if path.suffix == PROJECT_SUFFIX:
            self.open_project(path)
            return
        if self.open_project_for(path):
            self.add_media(path)

    def open_project_for(self, media: Path) -> bool:
        """Make the project beside ``media`` the open one: already open, opened, or started
        (once unsaved work is saved or discarded); True when it is open."""
        project_path = project_path_for(media)
        if project_path == self.model.path:
            return True
        if project_path.exists() or autosave_path(project_path).exists():
            self.open_project(project_path)
        elif self.may_leave_project():
            self.session_closing.emit()
            self.model.reset(Project(), project_path)
        return self.model.path == project_path

    def may_leave_project(self) -> bool:
        """Whether the open project may be closed: saved, or the user saved or discarded."""
        if not self.model.is_dirty:
            return True
        answer = self.ask.save_changes()
        if answer == "cancel" or (answer == "save" and not self.save()):
            return False
        if answer == "discard" and self.model.path is not None:
            autosave_path(self.model.path).unlink(missing_ok=True)
        return True

    def open_project(self, path: Path) -> None:
        """Read a project (offering its autosave), relink moved media, show its first clip."""
        if path != self.model.path and not self.may_leave_project():
            return
        try:
            project = read_project(path)
        except InputError as exc:
            if not (has_newer_autosave(path) and self.ask.restore_autosave(path)):
                self.notifier.error("Cannot open project",
                                    f"{exc}\n\nNothing was opened and nothing was changed: "
                                    f"{path.name} is as it was.")
                return
            project = None
        self.session_closing.emit()
        self.model.reset(project if project is not None else Project(), path)
        if has_newer_autosave(path) and (project is None or self.ask.restore_autosave(path)):
            try:
                restored = read_project(autosave_path(path))
            except InputError as exc:
                self.notifier.error("Cannot restore", str(exc))
            else:
                push_edit(self.model, restored, "restore unsaved work", Change("structure"))
                self.model.select_first()
        self._relink_missing()
        self._check_media()
        self._remember_recent(path)
        self.clip_chosen.emit()

    def _check_media(self) -> None:
        """In the background: whether any clip's media changed since it was added; if so,
        the user is told what and asked whether to take the files as they are now (nothing
        changes unless they agree)."""
        path, project = self.model.path, self.model.project
        media = [clip.media_path for clip in project.clips]

        def checked(changed: dict[int, str]) -> None:
            now = [clip.media_path for clip in self.model.project.clips]
            if not changed or self.model.path != path or now != media:
                return   # another project, or clips added or moved meanwhile: next time
            names = [project.clips[idx].name for idx in changed]
            if self.ask.media_changed(names):
                push_edit(self.model, with_media_accepted(self.model.project, changed),
                          "accept changed media", Change("structure"))

        # jobs of their own: reading each clip's media must not hold up opening the first
        self._media_jobs.run(lambda: changed_media(project, path), checked,
                             lambda why: self.notifier.status(f"media not checked: {why}",
                                                              STATUS_MS))

    def _relink_missing(self) -> None:
        path = self.model.path
        for clip_idx in missing_media(path, self.model.project):
            stored = self.model.project.clips[clip_idx].media_path
            chosen = self.ask.relink(stored, path.parent)
            if chosen is not None:
                push_edit(self.model, relink_clip(self.model.project, path, clip_idx, chosen),
                          f"relink {Path(stored).name}", Change("clip", clip=clip_idx))

    def add_media(self, media: Path) -> None:
        """Open media and find its camera (a still's EXIF) in the background, then add it to
        the project (or select its clip); the status bar says where the camera came from."""
        from dolphinfit.core.io.media import open_media

        path = self.model.path

        def read() -> tuple[ClipEntry, str]:
            with open_media(media) as source:
                return clip_entry_for(media, path.parent, source)

        def opened(found: tuple[ClipEntry, str]) -> None:
            if self.model.path != path:
                return   # another project by now: the media was not added to it
            entry, note = found
            project, clip_idx = project_with_clip(self.model.project, entry)
            if project is not self.model.project:
                push_edit(self.model, project, f"add {media.name}", Change("structure"))
                if note:
                    self.notifier.status(note, STATUS_MS)
            self.model.select(clip_idx)
            self.clip_chosen.emit()

        self.jobs.run(read, opened, lambda why: self.notifier.error("Cannot open media", why))

    def save(self, path: Path | None = None) -> bool:
        """Write the project (to ``path``: Save As); False when it could not be written."""
        old = self.model.path
        target = path or old
        if target is None:
            return False
        project = self.model.project
        if old is not None and target.parent.resolve() != old.parent.resolve():
            project = rebase_media(project, old.parent, target.parent)
        try:
            write_project(target, project)
        except OSError as exc:
            self.notifier.error("Cannot save", f"{target}: {exc.strerror or exc}")
            return False
        if old is not None and target != old:
            autosave_path(old).unlink(missing_ok=True)
        if project is not self.model.project:
            self.model.reset(project, target)
        elif target != old:
            self.model.set_path(target)
        self.model.mark_saved()
        self._remember_recent(target)
        self.notifier.status(f"saved {target}", 5000)
        return True

    def shutdown(self) -> None:
        """Wait for a media check still reading (closing)."""
        self._media_jobs.wait()

    def _remember_recent(self, path: Path) -> None:
        try:
            add_recent(path)
        except OSError as exc:
            self.notifier.status(f"recent projects not updated: {exc.strerror or exc}",
                                 STATUS_MS)
