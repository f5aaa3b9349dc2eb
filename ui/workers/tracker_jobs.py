"""Tracking jobs for a JobWorker (ui/workers/job_worker.py): a mask back-end (the network or the
colour tracker, core.segment.backends) run from a seed frame forwards, backwards or both ways,
merged into the clip's existing masks.

The tracker (core/segment/tracker.py) tracks from its seed to the end of the frames it is
given and then back to their start; a job gives it a view of the clip's frames in the order to
track (from the seed frame on, from the seed frame back, or all), so that each direction is
one of its passes. Frames outside the tracked range keep their existing masks.
"""

import threading
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Literal

import numpy as np

from dolphinfit.core.device import DEFAULT_DEVICE, resolve_device
from dolphinfit.core.io.frame_source import FrameSource
from dolphinfit.core.io.masks import MaskTrack, check_against_clip
from dolphinfit.core.io.media import open_media
from dolphinfit.core.progress import Progress, ProgressCallback
from dolphinfit.core.segment.backends import DEFAULT_BACKEND, make_segmenter
from dolphinfit.core.segment.segmenter import BoxSeed, FrameTracked, PointSeed, TrackingCancelled
from dolphinfit.ui.workers.job_worker import DEVICE_SETTING, Job

Direction = Literal["forward", "backward", "both"]
DIRECTIONS = ("forward", "backward", "both")
BLOCK_BYTES = 256 * 2**20  # frames decoded ahead, in ascending order, for a backward pass


class _FrameView:
    """Frames ``indices[i]`` of ``source`` as frame i (core.segment.segmenter.Frames).

    A request below the last one decodes a block of frames up to it in ascending order, so a
    backward pass does not seek for every frame.
    """

    def __init__(self, source: FrameSource, indices: range) -> None:
        self._source = source
        self._indices = indices
        clip = source.clip
        self._block_len = max(1, BLOCK_BYTES // (clip.width_px * clip.height_px * 3))
        self._block: dict[int, np.ndarray] = {}
        self._last = -1

    def __len__(self) -> int:
        return len(self._indices)

    def __getitem__(self, view_idx: int) -> np.ndarray:
        frame_idx = self._indices[view_idx]
        going_back, self._last = frame_idx < self._last, frame_idx
        if frame_idx not in self._block and going_back:
            first = max(0, frame_idx - self._block_len + 1)
            self._block = dict(self._source.frames(range(first, frame_idx + 1)))
        frame = self._block.get(frame_idx)
        return self._source[frame_idx] if frame is None else frame


@dataclass(frozen=True, eq=False)
class Tracked:
    """A tracking job's outcome: the clip's whole MaskTrack, how many frames the tracker
    reached, and whether it reached all it was asked to (False: cancelled, the frames it had
    tracked kept)."""

    track: MaskTrack
    num_tracked: int
    complete: bool = True


def _order(start_frame: int, num_frames: int, direction: Direction) -> range:
    """The clip's frames in the order one tracker run visits them (the seed frame first)."""
    if direction == "forward":
        return range(start_frame, num_frames)
    if direction == "backward":
        return range(start_frame, -1, -1)
    return range(num_frames)


def _merged(tracked: MaskTrack, order: range, num_frames: int, existing: MaskTrack | None,
            kept: np.ndarray | None, start_frame: int,
            segmented: set[int] | None = None) -> MaskTrack:
    """The clip's track of ``num_frames``: ``tracked`` (frames of the view ``order``; of
    those only ``segmented`` when given) over ``existing`` (empty if None); frame
    ``start_frame`` gets ``kept`` instead when given."""
    view_of = {frame_idx: view_idx for view_idx, frame_idx in enumerate(order)
               if segmented is None or frame_idx in segmented}
    width, height = tracked.width_px, tracked.height_px

    def load(frame_idx: int) -> np.ndarray:
        if kept is not None and frame_idx == start_frame:
            return kept
        if frame_idx in view_of:
            return tracked.mask(view_of[frame_idx])
        return existing.mask(frame_idx)  # only visible frames load: from existing here

    is_visible = (np.zeros(num_frames, bool) if existing is None
                  else existing.is_visible.copy())
    is_visible[list(view_of)] = tracked.is_visible[list(view_of.values())]
    if kept is not None:
        is_visible[start_frame] = kept.any()
    return MaskTrack(is_visible, width, height, tracked.source, load)


def track_job(media_path: Path | str, seed: PointSeed | BoxSeed | np.ndarray,
              start_frame: int, direction: Direction,
              existing: MaskTrack | None = None, backend: str = DEFAULT_BACKEND,
              checkpoint: Path | None = None, only_frames: Sequence[int] | None = None,
              device: str = DEFAULT_DEVICE) -> Job:
    """A job tracking the animal from frame ``start_frame`` in ``direction`` and returning the
    clip's whole MaskTrack as ``Tracked`` (frames outside the tracked range as in
    ``existing``; cancelled once tracking has begun, the frames tracked so far and the others
    as in ``existing``).
    ``checkpoint``, ``only_frames`` (clip frames) and ``device`` (a core.device name,
    resolved in the job) go to the back-end (make_segmenter).

    ``seed``: a click or a box on that frame (its own ``frame_idx`` is ignored), or that
    frame's corrected (H, W) bool mask ("re-track from here"): the tracker starts from a box
    around it and the frame keeps the mask as given. Progress is core.progress's contract
    (stage "track", frames tracked, each report's preview the FrameTracked of a clip frame);
    core.progress.Cancelled when cancelled before any frame is tracked.
    """
    if direction not in DIRECTIONS:
        raise ValueError(f"direction must be one of {DIRECTIONS}, got {direction!r}")
    kept = None
    if isinstance(seed, np.ndarray):
        kept = seed != 0
        seed = BoxSeed.around(kept, start_frame)

    def job(progress: ProgressCallback, cancel: threading.Event) -> MaskTrack:
        with open_media(media_path) as source:
            if existing is not None:
                check_against_clip(existing, source.clip)
            order = _order(start_frame, len(source), direction)
            if start_frame not in order:
                raise ValueError(f"start frame {start_frame} is outside the clip "
                                 f"(0…{len(source) - 1})")
            view_seed = replace(seed, frame_idx=order.index(start_frame))
            view_only = (None if only_frames is None
                         else [order.index(t) for t in only_frames if t in order])
            num_frames = len(source)

            def in_clip_frames(report: Progress) -> None:  # previews name the clip's frames
                if isinstance(report.preview, FrameTracked):
                    report = replace(report, preview=replace(
                        report.preview, frame_idx=order[report.preview.frame_idx]))
                progress(report)

            segmenter = make_segmenter(backend, view_only, checkpoint,
                                       resolve_device(device, DEVICE_SETTING))
            try:
                tracked = segmenter.segment(_FrameView(source, order), view_seed,
                                            in_clip_frames, cancel)
            except TrackingCancelled as stop:  # the frames it reached are kept
                reached = {order[view_idx] for view_idx in stop.visited}
                return Tracked(_merged(stop.track, order, num_frames, existing, kept,
                                       start_frame, reached), len(reached), complete=False)
        # a back-end limited to some frames leaves the others' masks as they were
        segmented = None if only_frames is None else {*map(int, only_frames), start_frame}
        return Tracked(_merged(tracked, order, num_frames, existing, kept, start_frame,
                               segmented), len(order if segmented is None else segmented))

    return job
