"""Per-frame dolphin masks: a PNG folder, a mask video or an .npz file; checks against the
clip; visibility flags; export.

Formats (DESIGN.md §8):

- **PNG folder**: one 8-bit PNG per frame named by its zero-based index (``%06d.png``);
  non-zero pixels are dolphin. A frame without a file is not visible.
- **Mask video**: one frame per clip frame; dolphin where the brightest channel is at least
  128 (lossy codecs smear a 0/255 mask, so "non-zero" would not do).
- **.npz**: ``masks`` (T, H, W), non-zero = dolphin, and optionally ``is_visible`` (T,) bool.

A frame is visible when it has a mask with at least one dolphin pixel (and, in an .npz, its
``is_visible`` is set); frames that are not visible are skipped by the fit, never fitted to an
empty mask. This is how an external segmenter's output (SAM-family models, for example) comes
in: write its masks in one of these formats.
"""

import re
import zipfile
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.atomic import atomic_folder, atomic_path
from dolphinfit.core.io.output_paths import check_output_file, check_output_folder
from dolphinfit.core.io.report import format_runs, list_some
from dolphinfit.core.io.video import Clip, VideoReader

PNG_NAME = "{:06d}.png"  # DESIGN.md §8
PNG_PATTERN = re.compile(r"^(\d+)\.png$", re.IGNORECASE)
VIDEO_THRESHOLD = 128  # grey level from which a mask-video pixel is dolphin
NPZ_SUFFIX = ".npz"
MASK_IMAGE_SUFFIXES = (".png", ".tif", ".tiff", ".bmp")  # a still's mask: lossless images
MASK_VALUE = 255  # written for dolphin pixels in PNGs
# A mask covering more of the frame than this is blank white or inverted (water marked as
# dolphin): a dolphin seen from 1 m or more never fills its frame.
MAX_COVERAGE = 0.9


@dataclass(frozen=True, eq=False)
class MaskTrack:
    """Per-frame masks of a clip, loaded on demand.

    is_visible: (T,) bool. width_px, height_px: mask size. source: where the masks come from,
    one line. load: frame index → (H, W) bool mask, called only for visible frames.
    (``eq=False``: arrays have no single truth value, so instances compare by identity.)
    """

    is_visible: np.ndarray
    width_px: int
    height_px: int
    source: str
    load: Callable[[int], np.ndarray]

    @property
    def num_frames(self) -> int:
        """T, the number of frames."""
        return self.is_visible.shape[0]

    def mask(self, frame_idx: int) -> np.ndarray:
        """Frame ``frame_idx``'s (H, W) bool mask; all False where the dolphin is not visible."""
        if not 0 <= frame_idx < self.num_frames:
            raise IndexError(f"frame {frame_idx} is outside the masks (0…{self.num_frames - 1})")
        if not self.is_visible[frame_idx]:
            return np.zeros((self.height_px, self.width_px), dtype=bool)
        return self.load(frame_idx)

    def stack(self) -> np.ndarray:
        """All masks in memory: (T, H, W) bool."""
        return np.stack([self.mask(t) for t in range(self.num_frames)])

    @classmethod
    def from_array(cls, masks: np.ndarray, source: str,
                   is_visible: np.ndarray | None = None) -> "MaskTrack":
        """Masks held in memory: (T, H, W), non-zero = dolphin; visible where non-empty (and
        ``is_visible``, if given)."""
        masks = np.asarray(masks) != 0
        visible = masks.any(axis=(1, 2))
        if is_visible is not None:
            visible &= np.asarray(is_visible, dtype=bool)
        return cls(visible, masks.shape[2], masks.shape[1], source, masks.__getitem__)


def _read_png(path: Path) -> np.ndarray:
    """(H, W) bool: non-zero pixels of any channel; InputError naming an unreadable file."""
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise InputError(f"{path}: not a readable PNG image")
    return image.any(axis=2) if image.ndim == 3 else image != 0


def _check_coverage(where: str, coverage: np.ndarray, names: Callable[[int], str]) -> None:
    """InputError naming the frames (``names``: frame index → file or frame name) whose masks
    cover more than MAX_COVERAGE of the frame; ``coverage``: (T,) fraction of dolphin pixels."""
    full = np.flatnonzero(coverage > MAX_COVERAGE)
    if full.size:
        raise InputError(f"{where}: {full.size} mask(s) cover more than {MAX_COVERAGE:.0%} of "
                         f"the frame (all white or inverted; non-zero pixels are dolphin): "
                         f"{list_some([names(int(t)) for t in full])}")


def check_not_empty(track: MaskTrack) -> None:
    """InputError naming the source when no mask marks any dolphin pixel."""
    if not track.is_visible.any():
        raise InputError(f"{track.source}: all {track.num_frames} masks are empty (frames "
                         f"{format_runs(~track.is_visible)}): no pixel marks the dolphin "
                         "(non-zero pixels are dolphin)")


def _check_size(where: str, mask_hw: tuple[int, ...], expected_hw: tuple[int, int]) -> None:
    if tuple(mask_hw) != tuple(expected_hw):
        raise InputError(f"{where}: mask is {mask_hw[1]}x{mask_hw[0]} px, expected "
                         f"{expected_hw[1]}x{expected_hw[0]} px")


def read_png_folder(folder: Path, clip: Clip | None = None) -> MaskTrack:
    """Masks from ``folder/%06d.png`` (every file is read once to check size and visibility).

    Without ``clip`` the track ends at the highest index found.
    """
    files = {int(m.group(1)): p for p in folder.iterdir()
             if (m := PNG_PATTERN.match(p.name)) and p.is_file()}
    if not files:
        raise InputError(f"{folder}: no mask PNGs named by frame index (%06d.png)")
    num_frames = clip.num_frames if clip is not None else max(files) + 1
    beyond = sorted(i for i in files if i >= num_frames)
    if beyond:
        raise InputError(f"{files[beyond[0]]}: frame {beyond[0]} is beyond the clip's "
                         f"{num_frames} frames")
    size_hw = (clip.height_px, clip.width_px) if clip is not None else None
    coverage = np.zeros(num_frames)
    for idx, path in sorted(files.items()):
        mask = _read_png(path)
        size_hw = size_hw or mask.shape
        _check_size(str(path), mask.shape, size_hw)
        coverage[idx] = mask.mean()
    _check_coverage(str(folder), coverage, lambda idx: files[idx].name)
    visible = coverage > 0
    return MaskTrack(visible, size_hw[1], size_hw[0], f"png folder {folder}",
                     lambda idx: _read_png(files[idx]))


def read_mask_image(path: Path, clip: Clip | None = None) -> MaskTrack:
    """The mask of a still: one image file (PNG, TIFF, …; non-zero pixels are the animal)."""
    mask = _read_png(path)
    if clip is not None:
        _check_size(str(path), mask.shape, (clip.height_px, clip.width_px))
    return MaskTrack(np.array([bool(mask.any())]), mask.shape[1], mask.shape[0],
                     f"mask image {path}", lambda _: mask)


def read_mask_video(path: Path, clip: Clip | None = None) -> MaskTrack:
    """Masks from a video, one frame per clip frame (decoded once here for visibility)."""
    reader = VideoReader(path)
    if clip is not None:
        _check_size(str(path), (reader.clip.height_px, reader.clip.width_px),
                    (clip.height_px, clip.width_px))

    def load(idx: int) -> np.ndarray:
        return reader[idx].max(axis=2) >= VIDEO_THRESHOLD

    coverage = np.array([load(t).mean() for t in range(len(reader))])
    _check_coverage(str(path), coverage, lambda idx: f"frame {idx}")
    visible = coverage > 0
    return MaskTrack(visible, reader.clip.width_px, reader.clip.height_px,
                     f"mask video {path}", load)


def read_npz(path: Path, clip: Clip | None = None) -> MaskTrack:
    """Masks from an .npz with ``masks`` (T, H, W) and optional ``is_visible`` (T,)."""
    try:
        with np.load(path, allow_pickle=False) as data:
            masks = data["masks"]
            is_visible = data["is_visible"] if "is_visible" in data.files else None
    except KeyError:
        raise InputError(f"{path}: no 'masks' array in the .npz file") from None
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
        raise InputError(f"{path}: not a readable .npz file, truncated or damaged "
                         f"({exc})") from None
    if masks.ndim != 3:
        raise InputError(f"{path}: 'masks' has shape {masks.shape}, expected (T, H, W)")
    if is_visible is not None and is_visible.shape != masks.shape[:1]:
        raise InputError(f"{path}: 'is_visible' has shape {is_visible.shape}, expected "
                         f"({masks.shape[0]},)")
    if clip is not None:
        _check_size(str(path), masks.shape[1:], (clip.height_px, clip.width_px))
    _check_coverage(str(path), (masks != 0).mean(axis=(1, 2)), lambda idx: f"frame {idx}")
    return MaskTrack.from_array(masks, f"npz {path}", is_visible)


def check_against_clip(track: MaskTrack, clip: Clip) -> None:
    """InputError unless ``track`` has the clip's frame count and frame size."""
    where = track.source
    if track.num_frames != clip.num_frames:
        raise InputError(f"{where}: {track.num_frames} frames of masks for the "
                         f"{clip.num_frames} frames of {clip.path}")
    _check_size(where, (track.height_px, track.width_px), (clip.height_px, clip.width_px))


def read_masks(path: Path | str, clip: Clip | None = None) -> MaskTrack:
    """Masks from a PNG folder, an .npz, a still's mask image or a mask video (by what
    ``path`` is), checked against ``clip`` when given; InputError when no mask marks the
    dolphin."""
    path = Path(path)
    if path.is_dir():
        track = read_png_folder(path, clip)
    elif not path.exists():
        raise InputError(f"{path}: no such file or folder")
    elif path.suffix.lower() == NPZ_SUFFIX:
        track = read_npz(path, clip)
    elif path.suffix.lower() in MASK_IMAGE_SUFFIXES:
        track = read_mask_image(path, clip)
    else:
        track = read_mask_video(path, clip)
    if clip is not None:
        check_against_clip(track, clip)
    check_not_empty(track)
    return track


def _is_hidden_file(entry: Path) -> bool:
    return entry.name.startswith(".") and entry.is_file()


def check_mask_folder(folder: Path) -> Path:
    """``folder`` if mask PNGs can be written there: new, or holding nothing but mask PNGs
    (and hidden files). Writing replaces the whole folder, so anything else is refused."""
    check_output_folder(folder)
    if folder.is_dir():
        foreign = sorted(p.name for p in folder.iterdir()
                         if not (PNG_PATTERN.match(p.name) and p.is_file()) and
                         not _is_hidden_file(p))
        if foreign:
            raise InputError(f"{folder}: holds other things than mask PNGs "
                             f"({list_some(foreign)}); masks go into a folder of their own")
    return folder


def write_png_folder(track: MaskTrack, folder: Path) -> None:
    """Write every frame as ``folder/%06d.png`` (0 or 255; empty where not visible).

    The PNGs are written into a folder beside ``folder`` that then replaces it (hidden files
    are kept), so a kill leaves the old masks or the new ones, never a mix.
    """
    check_mask_folder(folder)
    with atomic_folder(folder, carry=_is_hidden_file) as tmp:
        for idx in range(track.num_frames):
            image = track.mask(idx).astype(np.uint8) * MASK_VALUE
            if not cv2.imwrite(str(tmp / PNG_NAME.format(idx)), image):
                raise InputError(f"{folder / PNG_NAME.format(idx)}: cannot be written")


def write_npz(track: MaskTrack, path: Path) -> None:
    """Write ``masks`` (T, H, W) bool and ``is_visible`` (T,) to a compressed .npz, atomically
    (all frames are held in memory: use a PNG folder for long clips)."""
    with atomic_path(path) as tmp:
        np.savez_compressed(tmp, masks=track.stack(), is_visible=track.is_visible)


def check_mask_output(path: Path | str) -> Path:
    """``path`` if :func:`write_masks` can write there (see :func:`check_mask_folder`);
    InputError naming it otherwise."""
    path = Path(path)
    return check_output_file(path) if path.suffix.lower() == NPZ_SUFFIX else check_mask_folder(path)


def write_masks(track: MaskTrack, path: Path | str) -> None:
    """Write ``track`` to an .npz file or, for any other path, a PNG folder."""
    path = Path(path)
    if path.suffix.lower() == NPZ_SUFFIX:
        write_npz(track, path)
    else:
        write_png_folder(track, path)
