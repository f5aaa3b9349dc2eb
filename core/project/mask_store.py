"""A clip's masks kept with its project, and the per-frame facts the app shows about them.

Masks made or corrected in the app are stored losslessly beside the project file, as
``PROJECT.masks/<clip stem>.npz`` (core/io/masks.py's .npz format). Edits make new tracks:
``with_frame`` replaces one frame's mask, leaving the track it came from as it was.
Outlines are in image pixel coordinates (core/camera.py): pixel centres at integers.
"""

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.io.masks import NPZ_SUFFIX, MaskTrack, check_against_clip, read_npz, write_npz
from dolphinfit.core.io.video import Clip
from dolphinfit.core.project.fit_settings import clip_key
from dolphinfit.core.segment.regions import touches_border

MASKS_SUFFIX = ".masks"  # beside PROJECT.dolphinfit: PROJECT.masks/<clip stem>.npz


def masks_file(project_path: Path, clip_media: str | Path) -> Path:
    """Where a clip's masks are kept: ``PROJECT.masks/<clip key>.npz`` (fit_settings.clip_key)."""
    folder = project_path.with_name(project_path.stem + MASKS_SUFFIX)
    return folder / (clip_key(clip_media) + NPZ_SUFFIX)


def save_track(track: MaskTrack, path: Path) -> None:
    """Write ``track`` to ``path`` (.npz, atomically; its folder is made if needed)."""
    write_npz(track, path)


def load_track(path: Path, clip: Clip) -> MaskTrack:
    """The masks at ``path``; InputError naming the file unless they fit the clip's frame
    count and size."""
    track = read_npz(path, clip)
    check_against_clip(track, clip)
    return track


@dataclass(frozen=True, eq=False)
class Coverage:
    """Per-frame facts of a track, each (T,): ``visible`` (bool), ``touches_border`` (bool:
    a mask pixel in the outermost row or column) and ``area_px`` (int64, mask pixels)."""

    visible: np.ndarray
    touches_border: np.ndarray
    area_px: np.ndarray

    @property
    def num_frames(self) -> int:
        return self.visible.shape[0]


def coverage(track: MaskTrack) -> Coverage:
    """The Coverage of every frame of ``track`` (loads each visible frame once)."""
    touches = np.zeros(track.num_frames, dtype=bool)
    area_px = np.zeros(track.num_frames, dtype=np.int64)
    for frame_idx in np.flatnonzero(track.is_visible):
        mask = track.mask(int(frame_idx))
        area_px[frame_idx] = np.count_nonzero(mask)
        touches[frame_idx] = touches_border(mask)
    return Coverage(track.is_visible.copy(), touches, area_px)


@dataclass(frozen=True, eq=False)
class _Replaced:
    """A track's frame loader with some frames replaced by read-only masks held in memory."""

    base: Callable[[int], np.ndarray]
    masks: Mapping[int, np.ndarray]

    def __call__(self, frame_idx: int) -> np.ndarray:
        mask = self.masks.get(frame_idx)
        return self.base(frame_idx) if mask is None else mask


def with_frame(track: MaskTrack, frame_idx: int, mask: np.ndarray) -> MaskTrack:
    """A new track: ``track`` with frame ``frame_idx``'s mask replaced by (a copy of) ``mask``
    (H, W), non-zero = dolphin. The frame is visible when the new mask is not empty; the other
    frames still load as ``track``'s do. ValueError on a wrong size, IndexError on a wrong
    frame."""
    if not 0 <= frame_idx < track.num_frames:
        raise IndexError(f"frame {frame_idx} is outside the masks (0…{track.num_frames - 1})")
    if mask.shape != (track.height_px, track.width_px):
        raise ValueError(f"mask is {mask.shape[1]}x{mask.shape[0]} px, the track's are "
                         f"{track.width_px}x{track.height_px} px")
    new = np.asarray(mask) != 0
    new.flags.writeable = False
    base, masks = track.load, {}
    if isinstance(base, _Replaced):  # keep one level of replacements, however many edits
        base, masks = base.base, dict(base.masks)
    masks[int(frame_idx)] = new
    is_visible = track.is_visible.copy()
    is_visible[frame_idx] = new.any()
    return MaskTrack(is_visible, track.width_px, track.height_px, track.source,
                     _Replaced(base, masks))


def outlines(mask: np.ndarray) -> list[np.ndarray]:
    """The outer outlines of a (H, W) mask's regions: (N, 2) float64 (u, v) polygons through
    the centres of their edge pixels."""
    contours, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL,
                                   cv2.CHAIN_APPROX_SIMPLE)
    return [c.reshape(-1, 2).astype(np.float64) for c in contours]


def paint_segment(mask: np.ndarray, start_uv: tuple[float, float], end_uv: tuple[float, float],
                  radius_px: float, value: bool) -> tuple[slice, slice]:
    """Set to ``value``, in place, every pixel of the (H, W) bool ``mask`` whose centre lies
    within ``radius_px`` of the segment from ``start_uv`` to ``end_uv`` (image px): one step of
    a brush (True) or eraser (False) stroke. Returns the (rows, cols) window it touched."""
    (u0, v0), (u1, v1) = start_uv, end_uv
    height, width = mask.shape
    rows = slice(max(0, int(np.floor(min(v0, v1) - radius_px))),
                 min(height, int(np.ceil(max(v0, v1) + radius_px)) + 1))
    cols = slice(max(0, int(np.floor(min(u0, u1) - radius_px))),
                 min(width, int(np.ceil(max(u0, u1) + radius_px)) + 1))
    if rows.start >= rows.stop or cols.start >= cols.stop:
        return rows, cols
    v, u = np.mgrid[rows, cols]
    du, dv = u1 - u0, v1 - v0
    length2 = du * du + dv * dv
    # position of each pixel centre's nearest point along the segment, 0 at start, 1 at end
    along = np.clip(((u - u0) * du + (v - v0) * dv) / length2, 0, 1) if length2 else 0.0
    near = (u - u0 - along * du) ** 2 + (v - v0 - along * dv) ** 2 <= radius_px ** 2
    mask[rows, cols][near] = value
    return rows, cols
