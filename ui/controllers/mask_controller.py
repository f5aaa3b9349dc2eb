"""Masks in the app: the clip's masks loaded with its session, the current frame's outline on
the canvas, the coverage strip under the timeline, the built-in tracker started from a click
or re-run from a corrected frame, and brush / eraser corrections. Tracked and corrected masks
are kept losslessly in the project's folder (``PROJECT.masks/<clip>.npz``); pointing the clip
at them is an undoable edit."""

from dataclasses import replace
from collections.abc import Callable
from pathlib import Path

import numpy as np
from PySide6.QtCore import QObject, Signal

from dolphinfit.core.device import DEFAULT_DEVICE
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import MaskTrack, read_masks
from dolphinfit.core.progress import Progress
from dolphinfit.core.project.mask_store import (
    Coverage,
    coverage,
    masks_file,
    outlines,
    save_track,
    with_frame,
)
from dolphinfit.core.project.model import with_clip
from dolphinfit.core.project.project_file import relative_media_path
from dolphinfit.core.segment.backends import COLOUR, DEFAULT_BACKEND
from dolphinfit.core.segment.segmenter import FrameTracked, PointSeed
from dolphinfit.ui.workers.background import BackgroundJobs
from dolphinfit.ui.widgets.canvas import FrameCanvas
from dolphinfit.ui.state.commands import push_edit
from dolphinfit.ui.workers.job_worker import JobWorker
from dolphinfit.ui.widgets.mask_layer import MaskLayer
from dolphinfit.ui.state.project_model import Change, ProjectModel
from dolphinfit.ui.workers.tracker_jobs import Tracked, track_job
from dolphinfit.ui.state.viewer_state import Notifier, ViewerState


class MaskController(QObject):
    """Owns the mask layer, the tracking worker and the open clip's MaskTrack.

    ``coverage_changed(coverage or None)``: the open clip's mask coverage per frame, for the
    strip under the timeline; ``seeding(bool)``: the next click on the frame is the
    tracker's (True) or the measuring overlay's again (False); ``tracking_done(Tracked)``: a
    run ended, its masks kept. ``fit_frames()``: the current
    animal's fit frames (SAM-2 tracks only those)."""

    coverage_changed = Signal(object)
    seeding = Signal(bool)
    tracking_done = Signal(object)  # the whole run's Tracked (after the fit's frames too)

    def __init__(self, model: ProjectModel, state: ViewerState, notifier: Notifier,
                 jobs: BackgroundJobs, canvas: FrameCanvas,
                 fit_frames: Callable[[], list[int]], parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.model, self.state, self.notifier, self.jobs = model, state, notifier, jobs
        self.fit_frames = fit_frames
        self.layer = MaskLayer(canvas)
        self.layer.set_fill(False)  # an outline only: the body edge under it stays visible
        self.tracker = JobWorker(self)
        self.track: MaskTrack | None = None
        self._track_clip: int | None = None
        self._loaded: str | None = None  # the masks_path the track was read from or saved to
        self._reading: object | None = None  # the read of the clip's masks under way, if any
        self._target: tuple | None = None  # project path, clip index, limited to fit frames
        self._then: tuple | None = None  # start frame, the fit's frames, direction: next run
        self._edited_meanwhile: set[int] = set()  # frames corrected while a run tracks
        self._seeding = False
        self._coverage: Coverage | None = None  # what the coverage strip shows
        self.backend = DEFAULT_BACKEND  # who draws the masks (the Clip menu; a preference)
        self.sam2_checkpoint: Path | None = None  # asked for once (a preference)
        self.device = DEFAULT_DEVICE  # where the edge network runs (Edit menu; a preference)
        self.tracker.progress.connect(self._on_tracking_progress)
        self.tracker.finished.connect(self._on_tracked)
        self.tracker.failed.connect(lambda why: notifier.error("Tracking failed", why))
        self.tracker.cancelled.connect(lambda: notifier.status("tracking cancelled", 5000))
        self.layer.mask_edited.connect(self._on_edited)
        state.session_opened.connect(lambda _: self.load())
        state.session_closed.connect(self.load)
        state.frame_shown.connect(self.show_frame)
        canvas.image_clicked.connect(self._on_click)
        model.changed.connect(self._on_model_changed)

    # ----- loading and showing
    def _clip(self):
        """The open clip's entry; None without a session (or when its clip was removed)."""
        session, clips = self.state.session, self.model.project.clips
        if session is None or session.clip_idx >= len(clips):
            return None
        return clips[session.clip_idx]

    def load(self) -> None:
        """Read the open clip's masks (in the background); none: clear the views."""
        session, clip = self.state.session, self._clip()
        self.track, self._track_clip, self._reading = None, None, None
        self._loaded = None if clip is None else clip.masks_path
        self.layer.clear()
        self._emit_coverage(None)
        if clip is None or clip.masks_path is None:
            return
        masks = (self.model.path.parent / clip.masks_path).resolve()
        self._reading = reading = object()

        def done(track: MaskTrack) -> None:
            if self._reading is reading:
                self._reading = None
                self._set_track(session.clip_idx, track)

        def failed(why: str) -> None:
            if self._reading is reading:
                self._reading = None
                self.notifier.status(f"masks not read: {why}", 10_000)

        self.jobs.run(lambda: read_masks(masks, session.source.clip), done, failed)

    def _set_track(self, clip_idx: int, track: MaskTrack) -> None:
        if self.state.session_for(clip_idx) is None:
            return
        self.track, self._track_clip = track, clip_idx
        self._show_coverage(track)
        self.show_frame(self.state.frame_idx)

    def _show_coverage(self, track: MaskTrack) -> None:
        def shown(result: Coverage) -> None:
            if track is self.track:  # not a track replaced meanwhile
                self._emit_coverage(result)

        self.jobs.run(lambda: coverage(track), shown, lambda why: None)

    def _emit_coverage(self, shown: Coverage | None) -> None:
        self._coverage = shown
        self.coverage_changed.emit(shown)

    def _on_tracking_progress(self, progress: Progress) -> None:
        """The status line, and the coverage strip filled with each frame as it is tracked."""
        self.notifier.status(f"tracking ({self.backend}): frame {progress.step} of "
                             f"{progress.total}")
        frame = progress.preview
        if not isinstance(frame, FrameTracked) or self._target is None:
            return
        session = self.state.session_for(self._target[1])
        if session is None:  # another clip is open now
            return
        before = self._coverage
        if before is None:
            num_frames = session.source.clip.num_frames
            before = Coverage(np.zeros(num_frames, bool), np.zeros(num_frames, bool),
                              np.zeros(num_frames, np.int64))
        if frame.frame_idx < before.num_frames:
            after = Coverage(before.visible.copy(), before.touches_border.copy(),
                             before.area_px)
            after.visible[frame.frame_idx] = frame.visible
            after.touches_border[frame.frame_idx] = frame.touches_border
            self._emit_coverage(after)

    def show_frame(self, frame_idx: int) -> None:
        """The frame's mask outline (and, with a tool on, its mask to edit)."""
        track = self.track
        if track is None:
            return

        def shown(result: tuple[np.ndarray, list]) -> None:
            mask, polygons = result
            if frame_idx == self.state.frame_idx and track is self.track:
                self.layer.show_outlines(frame_idx, polygons)
                if self.layer.tool is not None:
                    self.layer.begin_edit(frame_idx, mask)

        def read() -> tuple[np.ndarray, list]:
            mask = track.mask(frame_idx)
            return mask, outlines(mask)

        self.jobs.run(read, shown, lambda why: None)

    def _on_model_changed(self, change: Change) -> None:
        clip = self._clip()
        if clip is None:
            if self.track is not None:  # the clip went (undo of adding it)
                self.track, self._track_clip = None, None
                self.layer.clear()
            return
        if clip.masks_path != self._loaded:
            self.load()  # chosen (Clip → Masks…), changed or undone

    # ----- tracking
    def arm_click_seed(self) -> None:
        """The next click on the frame seeds the tracker there (both directions)."""
        if self.state.session is None:
            return
        self._seeding = True
        self.seeding.emit(True)  # the click is the tracker's, not a length point
        self.notifier.status("click on the dolphin to track it from this frame")

    def _on_click(self, u: float, v: float, _modifiers: object) -> None:
        if not self._seeding:
            return
        self._seeding = False
        self.seeding.emit(False)
        self._start(PointSeed(u, v), "both")

    def retrack_here(self, every_frame: bool = False) -> None:
        """Track forwards and backwards from the current frame's (corrected) mask; on every
        frame of the clip when ``every_frame``, else as ``_start`` says."""
        if self.track is None or self._clip() is None:
            self.notifier.error("Re-track", "this clip has no masks yet: track from a click")
            return
        self._start(self.track.mask(self.state.frame_idx), "both", every_frame)

    def _start(self, seed: object, direction: str, every_frame: bool = False) -> None:
        """Track from ``seed`` on the current frame. The network and SAM-2 (about a second a
        frame and more) see only that frame and the frames the current animal's fit uses,
        unless ``every_frame``; the others keep the masks they had. From a click or a box
        they track that frame first, alone, so that its mask is kept (and "suggest edges"
        works) seconds after the click, then the fit's frames from it (a corrected mask to
        re-track from is kept as it is: no first run). The colour tracker, cheap and in need
        of every frame to follow the animal, always sees them all."""
        if self._clip() is None or self.model.path is None:
            return
        if self._reading is not None:  # the frames not tracked would lose the masks they have
            self.notifier.status("the clip's masks are still being read: track again in a "
                                 "moment", 5000)
            return
        only = None if every_frame or self.backend == COLOUR else self.fit_frames()
        frame_idx = self.state.frame_idx
        if only is not None and set(only) - {frame_idx} and not isinstance(seed, np.ndarray):
            self._then = (frame_idx, only, direction)
            only = [frame_idx]
        else:
            self._then = None
        self._run(seed, direction, only, frame_idx)

    def _run(self, seed: object, direction: str, only: list[int] | None,
             start_frame: int) -> None:
        """One tracking run from ``start_frame`` of the open clip (``_start``)."""
        session, path, clip = self.state.session, self.model.path, self._clip()
        media = (path.parent / clip.media_path).resolve()
        try:
            job = track_job(media, seed, start_frame, direction, self.track,
                            self.backend, self.sam2_checkpoint, only, device=self.device)
        except (InputError, ValueError) as exc:  # e.g. an empty mask to re-track from
            self._then = None
            self.notifier.error("Tracking", str(exc))
            return
        self._target = (path, session.clip_idx, only is not None)
        self._edited_meanwhile = set()
        self.tracker.run_job(job)

    def _on_tracked(self, outcome: Tracked) -> None:
        path, clip_idx, limited = self._target
        then, self._then = self._then, None
        if path != self.model.path or self.state.session_for(clip_idx) is None:
            self.notifier.error("Tracking", "the tracked masks were not kept: another clip or "
                                "project is open now")
            return
        track = outcome.track
        if self.track is not None and self._track_clip == clip_idx:
            for frame_idx in self._edited_meanwhile:  # brush strokes made meanwhile stay
                track = with_frame(track, frame_idx, self.track.mask(frame_idx))
        if not outcome.complete:
            self.notifier.status(f"tracking cancelled: the {outcome.num_tracked} frames "
                                 "tracked keep their new masks, the others the masks they had",
                                 10_000)
            self._keep_tracked(track, "track masks (cancelled)")
            self.tracking_done.emit(replace(outcome, track=track))
            return
        if then is not None:
            start_frame, fit_frames, direction = then
            if not track.is_visible[start_frame]:
                self.notifier.error("Tracking", f"no animal found at the click on frame "
                                    f"{start_frame}: click on the animal's body")
                return
            self._keep_tracked(track, "track masks")
            self.notifier.status(f"frame {start_frame} masked: now the {len(fit_frames)} "
                                 "frames the fit uses (Ctrl+. stops)")
            self._run(track.mask(start_frame), direction, fit_frames, start_frame)
            return
        rest = "; the fit's frames only (Clip → Track every frame for all)" if limited else ""
        self.notifier.status(f"{int(track.is_visible.sum())} of {track.num_frames} frames "
                             f"masked by {track.source}{rest}", 10_000)
        self._keep_tracked(track, "track masks")
        self.tracking_done.emit(replace(outcome, track=track))

    def _keep_tracked(self, track: MaskTrack, what: str) -> None:
        """Keep a run's masks and draw the shown frame's now: nothing else redraws it before
        the next frame change (a brush stroke draws its own, so ``_store`` does not)."""
        self._store(track, what)
        self.show_frame(self.state.frame_idx)

    # ----- corrections and storage
    def set_tool(self, tool: str | None) -> None:
        """Brush, eraser or none; a tool edits the current frame's mask."""
        self.layer.set_tool(tool)
        if tool is not None:
            if self.track is None:
                self.notifier.error("Masks", "this clip has no masks to correct yet")
                self.layer.set_tool(None)
                return
            self.show_frame(self.state.frame_idx)

    def _on_edited(self, frame_idx: int, mask: np.ndarray) -> None:
        if self.tracker.is_running and self._target is not None \
                and self._track_clip == self._target[1]:
            self._edited_meanwhile.add(frame_idx)
        if self.track is not None:
            self._store(with_frame(self.track, frame_idx, mask), "correct mask")

    def _store(self, track: MaskTrack, what: str) -> None:
        """Save the track beside the project (background) and point the clip at it."""
        clip_idx, path = self.state.session.clip_idx, self.model.path
        clip = self.model.project.clips[clip_idx]
        target = masks_file(path, clip.media_path)
        self.track, self._track_clip = track, clip_idx

        def saved(_: object) -> None:
            model = self.model
            if model.path != path or clip_idx >= len(model.project.clips):
                return  # another project is open now: the file is written, nothing points at it
            relative = relative_media_path(path.parent, target)
            current = model.project.clips[clip_idx]
            self._loaded = relative
            if current.masks_path != relative:
                push_edit(model, with_clip(model.project, clip_idx,
                                           replace(current, masks_path=relative)),
                          what, Change("clip", clip=clip_idx))
            if track is self.track:  # later edits may be queued: never step back to this one
                self._show_coverage(track)
            self.notifier.status(f"masks saved in {target.name}", 5000)

        self.jobs.run(lambda: save_track(track, target), saved,
                      lambda why: self.notifier.error("Masks not saved", why))

    def read_frame_mask(self, frame_idx: int, done: Callable[[np.ndarray], None],
                        what: str) -> None:
        """The open clip's mask of ``frame_idx``, read in the background, to ``done``; an
        error titled ``what`` when the clip has no masks or none on that frame."""
        session, clip = self.state.session, self._clip()
        if clip is None or clip.masks_path is None:
            self.notifier.error(what, "this clip has no masks: track the dolphin from a click "
                                "(Ctrl+T) or choose them with Clip → Masks…")
            return
        masks = (self.model.path.parent / clip.masks_path).resolve()

        def read() -> np.ndarray:
            track = read_masks(masks, session.source.clip)
            if not track.is_visible[frame_idx]:
                raise InputError(f"{masks}: no dolphin in the mask of frame {frame_idx}")
            return track.mask(frame_idx)

        self.jobs.run(read, done, lambda why: self.notifier.error(what, why))

    def use_masks(self, clip_idx: int, masks: Path) -> None:
        """Check that ``masks`` fit the open clip and keep a lossless copy with the project
        (in the background), then make them the clip's (undoable)."""
        media = self.state.session.source.clip
        project_path = self.model.path
        copy = masks_file(project_path, self.model.project.clips[clip_idx].media_path)

        def stored(_: object) -> None:
            clip = self.model.project.clips[clip_idx]
            push_edit(self.model, with_clip(self.model.project, clip_idx, replace(
                clip, masks_path=relative_media_path(project_path.parent, copy))),
                f"masks from {masks.name}", Change("clip", clip=clip_idx))
            self.load()  # the same file may hold new masks: read them again

        self.jobs.run(lambda: save_track(read_masks(masks, media), copy), stored,
                      lambda why: self.notifier.error("Cannot use these masks", why))

    def shutdown(self) -> None:
        self.tracker.shutdown()
