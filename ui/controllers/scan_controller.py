"""Scans in the app: each clip's scan (core/scan/) read back with the project, scans run in a
worker one clip after another with progress and cancel, saved beside the project and pointed
at by an undoable edit, each clip's status for the clip list, the pictures of the frame
picker, and the frames a user puts aside.

Scans are known by their file's absolute path, and clips by their media's, so that a Save As
elsewhere (which rewrites every relative path) neither loses them nor stops a scan; opening
another project forgets them and stops the scans under way.

``statuses_changed(list[ClipStatus])``: every clip's status, in clip order, whenever a scan,
a measurement or a fit changes it; ``scan_shown(ClipScan or None)``: the selected clip's
scan (None: not scanned yet)."""

import threading
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np
from PySide6.QtCore import QObject, Signal

from dolphinfit.core.io.media import open_media
from dolphinfit.core.progress import Progress, ProgressCallback
from dolphinfit.core.project.model import with_clip
from dolphinfit.core.project.project_file import media_path, relative_media_path
from dolphinfit.core.project.scan_store import (
    ClipStatus, clip_status, next_clip_needing_work, save_scan, scan_clip, scan_file,
)
from dolphinfit.core.scan.clip_scan import ClipScan
from dolphinfit.core.scan.frame_scores import FrameScore, ScanSettings
from dolphinfit.core.scan.scan_files import read_scan_json
from dolphinfit.core.scan.thumbnails import thumbnails
from dolphinfit.ui.state.commands import push_edit
from dolphinfit.ui.state.project_model import Change, ProjectModel
from dolphinfit.ui.state.viewer_state import Notifier
from dolphinfit.ui.workers.background import BackgroundJobs
from dolphinfit.ui.workers.job_worker import JobWorker

STATUS_MS = 10_000


class ScanController(QObject):
    """Reads, runs and keeps the project's scans (module doc)."""

    statuses_changed = Signal(object)   # list[ClipStatus]
    scan_shown = Signal(object)         # ClipScan | None, the selected clip's

    def __init__(self, model: ProjectModel, notifier: Notifier, jobs: BackgroundJobs,
                 settings: ScanSettings = ScanSettings(), parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.model, self.notifier, self.jobs, self.settings = model, notifier, jobs, settings
        self.worker = JobWorker(self)
        self.pictures = BackgroundJobs(self)  # decoding frames must not hold up saves
        self._scanner = None  # core.scan.scanner.Scanner, made in the worker on the first scan
        self._scans: dict[Path, ClipScan] = {}  # by the scan file's absolute path
        self._reading: set[Path] = set()
        self._queue: list[Path] = []            # absolute media of the clips still to scan
        self._running: Path | None = None       # the media being scanned
        self._generation = 0                    # one per project held: late answers dropped
        self._told: list[ClipStatus] = []       # the statuses last sent
        self.worker.progress.connect(self._on_progress)
        self.worker.finished.connect(self._on_scanned)
        self.worker.failed.connect(self._on_failed)
        self.worker.cancelled.connect(self._on_cancelled)
        model.changed.connect(self._on_model_changed)
        model.replaced.connect(self._forget)
        model.selection_changed.connect(self._show_selected)

    # ----- what is known
    def _scan_path(self, clip_idx: int) -> Path | None:
        relative = self.model.project.clips[clip_idx].scan_path
        if relative is None or self.model.path is None:
            return None
        return (self.model.path.parent / relative).resolve()

    def scan_of(self, clip_idx: int) -> ClipScan | None:
        """The clip's scan once read; None when not scanned (or still being read)."""
        path = self._scan_path(clip_idx)
        return None if path is None else self._scans.get(path)

    def statuses(self) -> list[ClipStatus]:
        return [clip_status(clip, self.scan_of(i))
                for i, clip in enumerate(self.model.project.clips)]

    def next_clip_needing_work(self) -> int | None:
        """The next clip after the selected one that needs work (ClipStatus.needs_work)."""
        return next_clip_needing_work(self.statuses(), self.model.clip_idx)

    def _forget(self) -> None:
        """Another project: its scans are not these, and the scans under way stop."""
        self._generation += 1
        self.cancel_all()
        self._scans.clear()
        self._reading.clear()

    def _on_model_changed(self, change: Change) -> None:
        if change.kind == "measurement":   # a length drawn or removed: the counts may change
            if self.statuses() != self._told:
                self._tell()
            return
        self._read_missing()
        self._tell()

    def _tell(self) -> None:
        self._told = self.statuses()
        self.statuses_changed.emit(self._told)
        self._show_selected()

    def _show_selected(self) -> None:
        clip_idx = self.model.clip_idx
        self.scan_shown.emit(None if clip_idx is None else self.scan_of(clip_idx))

    def _read_missing(self) -> None:
        """Read (in the background) the scans the project names and this has not read."""
        generation = self._generation
        for clip_idx in range(len(self.model.project.clips)):
            path = self._scan_path(clip_idx)
            if path is None or path in self._scans or path in self._reading:
                continue
            self._reading.add(path)
            self.jobs.run(lambda target=path: read_scan_json(target),
                          lambda scan, key=path: self._on_read(generation, key, scan),
                          lambda why, key=path: self._on_read_failed(key, why))

    def _on_read(self, generation: int, path: Path, scan: ClipScan) -> None:
        if generation == self._generation and path in self._reading:
            self._reading.discard(path)
            self._scans[path] = scan
            self._tell()

    def _on_read_failed(self, path: Path, why: str) -> None:
        self._reading.discard(path)
        self.notifier.status(f"scan not read ({why}): scan the clip again", STATUS_MS)

    # ----- scanning
    def _media(self, clip_idx: int) -> Path:
        return media_path(self.model.path, self.model.project.clips[clip_idx])

    def scan_selected(self) -> None:
        """Scan the selected clip (again, if it was scanned)."""
        clip_idx = self.model.clip_idx
        if clip_idx is None or self.model.path is None:
            self.notifier.error("Scan", "open or add a clip first")
            return
        self._enqueue([self._media(clip_idx)])

    def scan_unscanned(self) -> None:
        """Scan every clip of the project with more than one frame and no scan read (none
        made yet, or its file is gone or unreadable)."""
        if self.model.path is None:
            return
        todo = [self._media(i) for i, clip in enumerate(self.model.project.clips)
                if clip.kind != "image" and self.scan_of(i) is None
                and self._scan_path(i) not in self._reading]
        if not todo:
            self.notifier.status("every clip is scanned", STATUS_MS)
            return
        self._enqueue(todo)

    def _enqueue(self, media: list[Path]) -> None:
        self._queue += [m for m in media if m not in self._queue and m != self._running]
        if not self.worker.is_running:
            self._next()

    def cancel_all(self) -> bool:
        """Stop the scan under way and those queued (True if there was one)."""
        self._queue.clear()
        if self.worker.is_running:
            self.worker.cancel()
            return True
        return False

    def _clip_index(self, media: Path) -> int | None:
        if self.model.path is None:
            return None
        return next((i for i in range(len(self.model.project.clips))
                     if self._media(i) == media), None)

    def _next(self) -> None:
        """Start the next queued clip still in the project."""
        while self._queue and not self.worker.is_running:
            media = self._queue.pop(0)
            clip_idx = self._clip_index(media)
            if clip_idx is None:
                continue  # removed meanwhile
            path, project, settings = self.model.path, self.model.project, self.settings
            target = scan_file(path, project.clips[clip_idx].media_path).resolve()

            def job(progress: ProgressCallback, cancel: threading.Event) -> tuple:
                if self._scanner is None:  # the network loads torch: only when first scanning
                    from dolphinfit.core.scan.scanner import Scanner
                    self._scanner = Scanner()
                scan = scan_clip(path, project, clip_idx, settings, self._scanner, progress,
                                 cancel)
                save_scan(scan, target)
                return scan, target

            self._running = media
            self.worker.run_job(job)

    def _on_progress(self, progress: Progress) -> None:
        left = f"; {len(self._queue)} more clip{'s' if len(self._queue) != 1 else ''} queued" \
            if self._queue else ""
        name = self._running.name if self._running else ""
        self.notifier.status(f"scanning {name}: {progress.step} of {progress.total} samples, "
                             f"{progress.message}{left}")

    def _on_scanned(self, outcome: tuple[ClipScan, Path]) -> None:
        scan, target = outcome
        media, self._running = self._running, None
        clip_idx = self._clip_index(media)
        if clip_idx is not None:
            self._scans[target] = scan
            clip = self.model.project.clips[clip_idx]
            count = len(scan.animal_ids())
            self.notifier.status(f"{clip.name}: {count} animal{'s' if count != 1 else ''} "
                                 f"found in {len(scan.sampled_frames)} sampled frames "
                                 f"({scan.seconds:.0f} s)", STATUS_MS)
            relative = relative_media_path(self.model.path.parent, target)
            if clip.scan_path != relative:
                push_edit(self.model, with_clip(self.model.project, clip_idx,
                                                replace(clip, scan_path=relative)),
                          "scan clip", Change("clip", clip=clip_idx))
            else:
                self._tell()
        self._next()

    def _on_failed(self, why: str) -> None:
        name = self._running.name if self._running else "the clip"
        self._running = None
        self.notifier.error("Scan", f"{name}: {why}")
        self._next()

    def _on_cancelled(self) -> None:
        self._running = None
        self.notifier.status("scan cancelled: the clips scanned before keep their scans",
                             STATUS_MS)
        self._next()  # what was queued after the cancel (another project's clips)

    # ----- the frame picker's pictures
    def thumbnails(self, clip_idx: int, scores: list[FrameScore], size_px: int,
                   done: Callable[[dict[tuple[int, int], np.ndarray]], None]) -> None:
        """Pictures of the animal of each score of a clip, by (animal, frame), decoded in
        the background (their own thread: saves and mask reads do not wait), to ``done``."""
        if self.model.path is None:
            return
        media = self._media(clip_idx)

        def read() -> dict[tuple[int, int], np.ndarray]:
            with open_media(media) as source:
                return thumbnails(source, scores, size_px)

        self.pictures.run(read, done, lambda why: self.notifier.status(
            f"no pictures of the frames: {why}", STATUS_MS))

    # ----- frames put aside
    def toggle_rejected(self, clip_idx: int, animal: int, frame_idx: int) -> None:
        """Put a frame aside for an animal, or take it back (an undoable edit)."""
        clip = self.model.project.clips[clip_idx]
        pair = (animal, frame_idx)
        rejected = set(clip.rejected_frames) ^ {pair}
        what = "put frame aside" if pair in rejected else "take frame back"
        push_edit(self.model, with_clip(self.model.project, clip_idx,
                                        replace(clip, rejected_frames=tuple(rejected))),
                  what, Change("clip", clip=clip_idx))

    def shutdown(self) -> None:
        self._queue.clear()
        self.worker.shutdown()
        self.pictures.wait()
