"""The open clip: its session opened in the background when a clip is selected, its altitude
read again whenever the project's altitude setting for it changes (set, undone, restored), the
altitude of a frame for the results, and the Clip menu's altitude and camera commands.

It holds the viewer state's session; the window shows what it opens (``opened``) and what it
reads again (``telemetry_changed``)."""

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from PySide6.QtCore import QObject, Signal

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.lens import LensModel, read_lens
from dolphinfit.core.project.calibrations import clip_calibration
from dolphinfit.core.project.clip_cameras import CameraSetting, camera_setting, with_camera_setting
from dolphinfit.core.project.model import CAMERA_UNKNOWN, with_calibration, with_clip
from dolphinfit.core.project.project_file import media_path
from dolphinfit.core.project.results import frame_altitude
from dolphinfit.ui.dialogs.questions import Questions
from dolphinfit.ui.state.clip_session import ClipSession, open_session, read_session_telemetry
from dolphinfit.ui.state.commands import push_edit
from dolphinfit.ui.state.project_model import Change, ProjectModel
from dolphinfit.ui.state.viewer_state import Notifier, ViewerState, selected_clip
from dolphinfit.ui.workers.background import BackgroundJobs


class ClipSessions(QObject):
    """Opens, closes and refreshes the viewer state's clip session (module doc).

    ``opened(session)`` fires once the session is the state's, before the state's own
    ``session_opened``; ``telemetry_changed`` when the open clip's altitude was read again."""

    opened = Signal(object)
    telemetry_changed = Signal()

    def __init__(self, model: ProjectModel, state: ViewerState, ask: Questions,
                 notifier: Notifier, jobs: BackgroundJobs, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.model, self.state, self.ask = model, state, ask
        self.notifier, self.jobs = notifier, jobs
        self._opening: int | None = None
        model.changed.connect(self._on_model_changed)

    def close(self) -> None:
        """Close the open session (and forget one being opened)."""
        self._opening = None
        self.state.close()

    def open_current(self) -> None:
        """Open the selected clip's session in the background, unless it is open or opening."""
        clip_idx, path = self.model.clip_idx, self.model.path
        if clip_idx is None or path is None:
            return
        if self._opening == clip_idx or self.state.session_for(clip_idx) is not None:
            return
        clip = self.model.project.clips[clip_idx]
        if not media_path(path, clip).exists():
            self.notifier.status("this clip's media is missing: reopen the project to "
                                 "relink it", 10_000)
            return
        self.close()
        self._opening = clip_idx
        self.jobs.run(lambda: open_session(path, clip, clip_idx), self._on_opened,
                      self._on_failed)

    def _on_failed(self, why: str) -> None:
        self._opening = None
        self.notifier.error("Cannot open clip", why)

    def _on_opened(self, session: ClipSession) -> None:
        if self._opening == session.clip_idx:
            self._opening = None
        if session.clip_idx != self.model.clip_idx:
            session.close()  # the user moved on while it opened
            self.open_current()
            return
        self.state.session = session
        clip = self.model.project.clips[session.clip_idx]
        if clip.altitude != session.altitude:
            self._reload_telemetry()  # changed while the clip opened (a restored autosave)
        self.opened.emit(session)
        self.state.session_opened.emit(session.clip_idx)
        if clip.altitude is None:  # a new clip: its altitude comes first (SRT found if any)
            self.set_altitude()

    def _on_model_changed(self, change: Change) -> None:
        session, clips = self.state.session, self.model.project.clips
        if change.kind == "measurement" or session is None:
            return
        if session.clip_idx >= len(clips):
            self.close()
        elif clips[session.clip_idx].altitude != session.altitude:
            self._reload_telemetry()  # set, changed, undone or restored

    def _reload_telemetry(self) -> None:
        path, session = self.model.path, self.state.session
        clip = self.model.project.clips[session.clip_idx]

        def done(reloaded: ClipSession) -> None:
            if self.state.session is session:
                self.state.session = reloaded
                self.telemetry_changed.emit()

        self.jobs.run(lambda: read_session_telemetry(path, clip, session.clip_idx,
                                                     session.source),
                      done, lambda why: self.notifier.error("Cannot read altitude", why))

    def altitude_at(self, clip_idx: int, frame_idx: int) -> tuple[float, str]:
        """Altitude (m) and its error source for a frame of the open clip; InputError if none."""
        session = self.state.session_for(clip_idx)
        if session is None:
            raise InputError("the clip is still opening")
        spec = self.model.project.clips[clip_idx].altitude
        if spec != session.altitude:
            raise InputError("reading the altitude…")
        if session.telemetry is None:
            raise InputError(session.telemetry_error or "no altitude for this clip")
        return frame_altitude(session.telemetry, frame_idx), spec.source

    def calibrated_altitude(self, clip_idx: int, recorded_m: float) -> float | None:
        """A recorded altitude of the clip through its altitude calibration, as the results
        take it; None when the clip names none. InputError when its calibration cannot be
        fitted."""
        calibration = clip_calibration(self.model.project, clip_idx)
        return None if calibration is None else float(calibration.true_altitude(recorded_m))

    def _open_clip(self) -> int | None:
        """The selected clip when its session is open; an error said when none is selected."""
        clip_idx = selected_clip(self.model, self.notifier)
        return clip_idx if self.state.session is not None else None

    def set_altitude(self) -> None:
        """Ask for the open clip's altitude and set it (an undoable edit)."""
        clip_idx = self._open_clip()
        if clip_idx is None:
            return
        clip = self.model.project.clips[clip_idx]
        spec = self.ask.altitude(media_path(self.model.path, clip), self.model.path.parent,
                                 self.state.session.source.clip, clip.altitude)
        if spec is not None:
            push_edit(self.model, with_clip(self.model.project, clip_idx,
                                            replace(clip, altitude=spec)),
                      "set altitude", Change("clip", clip=clip_idx))

    def set_camera(self, selected: Sequence[int] = ()) -> None:
        """Ask for the open clip's camera and set it on that clip, the other ``selected``
        clips and, where asked, every clip of the open clip's video size, in one undoable
        edit. Each clip takes the lens model kept with the chosen preset where it has none
        of its own (core.project.clip_cameras); the clips' sizes and lenses are read in the
        background."""
        clip_idx = self._open_clip()
        if clip_idx is None:
            return
        clip = self.model.project.clips[clip_idx]
        media = self.state.session.source.clip
        size = (media.width_px, media.height_px)
        targets = sorted({clip_idx, *selected})
        answer = self.ask.camera(clip.camera, clip.preset_name, *size, len(targets))
        if answer is None:
            return
        path, project = self.model.path, self.model.project
        every_of_size = size if answer.is_for_every_clip_of_size else None
        self.jobs.run(lambda: camera_setting(path, project, answer.camera, answer.preset_name,
                                             targets, {clip_idx: size}, every_of_size),
                      lambda setting: self._apply_camera(path, setting),
                      lambda why: self.notifier.error("Camera", why))

    def _apply_camera(self, path: Path, setting: CameraSetting) -> None:
        """Set the camera read in the background, unless the project changed meanwhile."""
        if not setting.lenses:
            self.notifier.error("Camera", "no clip was set: " + "; ".join(setting.notes))
            return
        project = self.model.project
        after = with_camera_setting(project, setting) if self.model.path == path else None
        if after is None:
            return   # another project, or other clips, by now: the choice no longer applies
        targets = list(setting.lenses)
        text = "set camera" if len(targets) == 1 else f"set camera of {len(targets)} clips"
        if any(lens not in (None, project.clips[i].lens) for i, lens in setting.lenses.items()):
            text += " and its lens model"
        push_edit(self.model, after, text,
                  Change("clip", clip=targets[0] if len(targets) == 1 else None))
        if setting.notes:
            self.notifier.status("; ".join(setting.notes), 10_000)

    def set_lens(self) -> None:
        """Ask for a lens model (`dolphinfit calibrate lens`) for the open clip, read and
        check it in the background, then take the clip's measurements through it
        (undoable)."""
        clip_idx = self._open_clip()
        if clip_idx is None:
            return
        path = self.ask.lens_file()
        if path is None:
            return
        media = self.state.session.source.clip

        def read() -> LensModel:
            lens = read_lens(path)
            lens.check_image_size(media.width_px, media.height_px, str(path))
            return lens

        def chosen(lens: LensModel) -> None:
            clip = self.model.project.clips[clip_idx]
            push_edit(self.model, with_clip(self.model.project, clip_idx,
                                            replace(clip, lens=lens)),
                      f"lens model {path.name}", Change("clip", clip=clip_idx))

        self.jobs.run(read, chosen, lambda why: self.notifier.error("Lens model", why))

    def clear_lens(self) -> None:
        """Measure the open clip as clicked again, without its lens model (undoable)."""
        clip_idx = self._open_clip()
        if clip_idx is None:
            return
        clip = self.model.project.clips[clip_idx]
        if clip.lens is None:
            self.notifier.status("this clip has no lens model", 5000)
            return
        push_edit(self.model, with_clip(self.model.project, clip_idx, replace(clip, lens=None)),
                  "no lens model", Change("clip", clip=clip_idx))

    def calibrate_altitude(self) -> None:
        """Build the open clip's altitude calibration or edit the one it has, and choose the
        clips it corrects (an undoable edit); a new one's camera is chosen in the dialog (the
        clip's offered first) and no clip is ticked until the user ticks it."""
        clip_idx = self._open_clip()
        if clip_idx is None:
            return
        project = self.model.project
        clip = project.clips[clip_idx]
        if clip.camera is None:
            self.notifier.error("Altitude calibration", f"{clip.name}: {CAMERA_UNKNOWN}")
            return
        current = (None if clip.altitude_calibration is None
                   else project.calibration(clip.altitude_calibration))
        clips = [(i, c.name, c.camera.intrinsics().focal_px)
                 for i, c in enumerate(project.clips) if c.camera is not None]
        ticked = (set() if current is None else
                  {i for i, c in enumerate(project.clips)
                   if c.altitude_calibration == current.name})
        choice = self.ask.altitude_calibration(current, clip.camera, clip.preset_name, clips,
                                               ticked)
        if choice is not None:
            push_edit(self.model, with_calibration(
                project, choice.calibration, choice.clip_indices,
                replacing=None if current is None else current.name),
                "altitude calibration", Change("settings"))

