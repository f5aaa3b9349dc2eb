"""What the fit sees: the chosen frames, cut into regions of interest with exact intrinsics.

With ``use_roi`` (default) every frame is cropped at native resolution around its mask, one
crop size for the clip and the crop's top-left pixel per frame: the camera keeps its focal
length and the crop only shifts the principal point, so the metric is exact (DESIGN.md §3).
An animal more than twice ``fit_width_px`` wide is fitted at half that resolution (or a
quarter, …): each pixel the mean of 2 × 2, the intrinsics scaled with them, exact as well.
Without it, whole frames are downscaled to the paper's 720 px width, as the paper did.
"""

import math
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace

import cv2
import numpy as np
import torch
import torch.nn.functional as F

from dolphinfit.core.camera import NadirCamera
from dolphinfit.core.coverage import majority as coverage_majority
from dolphinfit.core.coverage import white_squares
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.reporter import PREPARE_STAGE
from dolphinfit.core.fit.whole_body import elongation, length_px, partial, widest_px
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.io.masks import MaskTrack
from dolphinfit.core.io.report import list_some
from dolphinfit.core.io.telemetry import Telemetry
from dolphinfit.core.io.video import Clip, crop_roi
from dolphinfit.core.limits import ALTITUDE_M
from dolphinfit.core.measure.edge_blur import edge_blur_px
from dolphinfit.core.measure.lens import LensModel, masks_off_centre_warning
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel
from dolphinfit.core.render.settings import Viewport
from dolphinfit.core.segment.regions import touches_border

ROI_MULTIPLE_PX = 8
ROI_ALIGN_PX = 2   # window corners on even pixels, so a 2× coarser copy of them is exact
EDGE_BLUR_FRAMES = 5   # frames the edge's blur is measured on (a fit has 8–35)


@dataclass(frozen=True, eq=False)
class FitData:
    """Frames, masks and cameras of a fit; T frames of a common H × W window."""

    frame_idx: np.ndarray        # (T,) clip frame indices
    time_s: np.ndarray           # (T,) seconds from the clip's start
    images: torch.Tensor         # (T, H, W, 3) float32 RGB in [0, 1]
    masks: torch.Tensor          # (T, H, W) float32, 1 = dolphin
    camera: NadirCamera          # T altitudes; intrinsics of the (possibly resized) frame
    viewport: Viewport           # the window of each frame
    clip_focal_px: float         # the clip's own focal length, px (the windows may be binned)
    warnings: tuple[str, ...]
    # the blur index of the animal's edge (``edge_blur_of``), clip px, read before any binning
    # (binning by 2 doubled it); NaN: not measured
    edge_blur_px: float = float("nan")
    # the masks' medians: the animal's width at its widest, clip px, and how many times as
    # long as wide they are (core.fit.whole_body); NaN: not measured
    animal_width_px: float = float("nan")
    elongation: float = float("nan")

    @property
    def num_frames(self) -> int:
        """T."""
        return len(self.frame_idx)

    @property
    def device(self) -> torch.device:
        """Where the tensors lie."""
        return self.images.device

    @property
    def clip_px_per_px(self) -> float:
        """Pixels of the clip per pixel of the windows (2 where binned by 2; 1920 / 720 in the
        paper's whole-frame mode)."""
        return self.clip_focal_px / self.camera.intrinsics.focal_px

    def every_frame(self) -> torch.Tensor:
        """(T,) int64 indices of all the frames, where the tensors lie."""
        return torch.arange(self.num_frames, device=self.device)

    def to(self, device: torch.device | str) -> "FitData":
        """The same data with its tensors on ``device`` (the same tensors where they lie
        there already)."""
        viewport = self.viewport
        return replace(self, images=self.images.to(device), masks=self.masks.to(device),
                       camera=replace(self.camera,
                                      altitude_m=self.camera.altitude_m.to(device)),
                       viewport=replace(viewport, x0_px=viewport.x0_px.to(device),
                                        y0_px=viewport.y0_px.to(device)))


def downscaled(data: FitData, factor: int, keep_area: bool = False) -> FitData | None:
    """The same frames at 1/``factor`` of the resolution (each pixel the mean of factor ×
    factor pixels, masks where at least half was dolphin, or with ``keep_area`` where the
    ``majority`` was), or None where the windows are not whole multiples of ``factor``
    (their blocks are then not the frame's, and the metric would not be exact)."""
    viewport, intrinsics = data.viewport, data.camera.intrinsics
    sizes = (viewport.width_px, viewport.height_px)
    if (any(size % factor for size in sizes) or bool((viewport.x0_px % factor).any())
            or bool((viewport.y0_px % factor).any())):
        return None
    images = F.avg_pool2d(data.images.permute(0, 3, 1, 2), factor).permute(0, 2, 3, 1)
    share = F.avg_pool2d(data.masks[:, None], factor)[:, 0]
    masks = (majority(share) if keep_area else share >= 0.5).to(data.masks.dtype)
    camera = replace(data.camera, intrinsics=intrinsics.binned(factor))
    coarse_viewport = Viewport(viewport.x0_px // factor, viewport.y0_px // factor,
                               viewport.width_px // factor, viewport.height_px // factor)
    return replace(data, images=images.contiguous(), masks=masks, camera=camera,
                   viewport=coarse_viewport)


def majority(share: torch.Tensor) -> torch.Tensor:
    """(T, H, W) bool: ``core.coverage.majority`` of ``share`` (T, H, W). Counting every tie
    in made the masks at half resolution 3.5 % larger in area (ties lie all along the
    outline); half of them keeps it (0.998 and 0.9997 of the area on the speed clip at 1080p
    and 4K). The coarse level of the fit keeps the rule it was tuned with: this one moved
    single clips of the tuning split by up to 2 points of volume (mean |volume| error 2.59 →
    2.75 %)."""
    white = torch.as_tensor(white_squares(*share.shape[1:]), device=share.device)
    return coverage_majority(share, white)


def edge_blur_of(data: FitData, max_frames: int = EDGE_BLUR_FRAMES) -> float:
    """The median blur index (core.measure.edge_blur) of the animal's edge over up to
    ``max_frames`` of ``data``'s frames, evenly spread, in pixels of the clip; NaN where no
    frame shows an edge."""
    picks = np.unique(np.linspace(0, data.num_frames - 1, max_frames).round().astype(int))
    blurs = [edge_blur_px(data.images[t].numpy(), data.masks[t].numpy() > 0.5) for t in picks]
    blurs = [b for b in blurs if np.isfinite(b)]
    return float(np.median(blurs)) * data.clip_px_per_px if blurs else float("nan")


def select_frames(clip: Clip, masks: MaskTrack,
                  config: FitConfig) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Frames to fit (in the time range, at the fit rate, with a visible dolphin inside the
    frame): their indices (T,), their masks (T, H, W) bool, and warnings."""
    candidates = config.frames_of(clip)
    chosen, chosen_masks, skipped_border, empty = [], [], [], []
    for idx in candidates:
        mask = masks.mask(int(idx))
        if not mask.any():
            empty.append(f"{int(idx)}")
            continue
        if touches_border(mask):
            skipped_border.append(int(idx))
            continue
        chosen.append(int(idx))
        chosen_masks.append(mask)
    warnings = []
    if empty and chosen:   # e.g. masks made for other frames than these (`masks --every`)
        warnings.append(f"{len(empty)} frame(s) skipped: no mask marks the dolphin (first: "
                        f"frame {empty[0]})")
    if skipped_border:
        warnings.append(f"{len(skipped_border)} frame(s) skipped: the dolphin touches the image "
                        f"border (first: frame {skipped_border[0]})")
    if not chosen:
        reasons = [f"{what} in frames {list_some(frames)}" for what, frames in (
            ("empty masks", empty),
            ("the dolphin touches the border", [str(i) for i in skipped_border])) if frames]
        raise InputError(f"{clip.path}: no frame with a visible dolphin in the chosen range "
                         f"({len(candidates)} frames looked at; {masks.source}: "
                         f"{'; '.join(reasons)})")
    return np.asarray(chosen, dtype=np.int64), np.stack(chosen_masks), warnings


def _altitude_possible(telemetry: Telemetry,
                       frame_idx: np.ndarray) -> tuple[np.ndarray, list[str]]:
    """Which chosen frames keep a possible altitude: a frame whose own altitude sample was
    impossible (0 m, a corrupt cue) is left out, named, not bridged from its neighbours;
    InputError when none is left."""
    impossible = (np.zeros(len(frame_idx), bool) if telemetry.is_impossible is None
                  else telemetry.is_impossible[frame_idx])
    if not impossible.any():
        return ~impossible, []
    where = f"{telemetry.source.describe()}: outside the plausible {ALTITUDE_M.text()}"
    if impossible.all():
        raise InputError(f"the altitude recorded at every fitted frame is impossible ({where})")
    frames = list_some([str(int(t)) for t in frame_idx[impossible]])
    return ~impossible, [f"{int(impossible.sum())} fitted frame(s) left out: the altitude "
                         f"recorded there is impossible (frames {frames}; {where})"]


def frame_altitudes(telemetry: Telemetry, frame_idx: np.ndarray) -> tuple[np.ndarray, list[str]]:
    """Altitude of each chosen frame, interpolating missing ones (with a warning)."""
    altitude = telemetry.altitude_m
    known = ~np.isnan(altitude)
    if not known.any():
        raise InputError(f"no altitude for any frame ({telemetry.source.describe()})")
    missing = frame_idx[~known[frame_idx]]
    warnings = []
    if len(missing):
        warnings.append(f"altitude missing for {len(missing)} fitted frame(s), interpolated "
                        f"(first: frame {int(missing[0])})")
    frames = np.arange(len(altitude))
    return np.interp(frame_idx, frames[known], altitude[known]), warnings


def prepare_data(clip: Clip, read_frame: Callable[[int], np.ndarray], masks: MaskTrack,
                 telemetry: Telemetry, intrinsics: CameraIntrinsics, config: FitConfig,
                 progress: ProgressCallback | None = None,
                 cancel: threading.Event | None = None,
                 lens: LensModel | None = None) -> FitData:
    """Cut the chosen frames and masks for the fit; ``read_frame`` gives (H, W, 3) uint8 RGB.
    With a ``lens``, frames and masks are first undistorted (as its own pinhole camera would
    have seen them, so the fit's pinhole camera projects as the lens did); without one, a
    warning when the animal reaches far off-centre.

    Reports each frame read as the fit's "prepare" stage (step 0 of the fit's steps,
    core.fit.reporter) and raises core.progress.Cancelled between frames once ``cancel`` is set.
    """
    frame_idx, masks_np, warnings = select_frames(clip, masks, config)
    clip_focal_px = intrinsics.focal_px
    if lens is None:
        warnings += [w for w in [masks_off_centre_warning(masks_np, intrinsics)] if w]
    else:
        lens.check_image_size(clip.width_px, clip.height_px, "the lens model")
        frame_idx, masks_np, lens_warnings = _masks_through_lens(clip, frame_idx, masks_np, lens)
        warnings += lens_warnings + [w for w in [lens.focal_warning(intrinsics)] if w]
        read_frame = _through_lens(read_frame, lens)
    possible, impossible_warnings = _altitude_possible(telemetry, frame_idx)
    frame_idx, masks_np = frame_idx[possible], masks_np[possible]
    warnings += impossible_warnings
    altitude, altitude_warnings = frame_altitudes(telemetry, frame_idx)
    kept, partial_warnings = _whole_frames(frame_idx, masks_np, altitude, clip_focal_px)
    frame_idx, masks_np, altitude = frame_idx[kept], masks_np[kept], altitude[kept]
    warnings += partial_warnings
    animal_width = float(np.median([widest_px(mask) for mask in masks_np]))
    frames = _read_frames(read_frame, frame_idx, config.total_steps, progress, cancel)
    factor = 1
    if config.use_roi:
        factor = fit_factor(animal_width, config)
        x0, y0, width, height = _roi_windows(masks_np, config.roi_margin_px, factor)
        images = np.stack([crop_roi(frame, int(a), int(b), width, height)
                           for frame, a, b in zip(frames, x0, y0)])
        cut = np.stack([crop_roi(m.astype(np.uint8), int(a), int(b), width, height)
                        for m, a, b in zip(masks_np, x0, y0)]) > 0
        viewport = Viewport(torch.as_tensor(x0), torch.as_tensor(y0), width, height)
    else:
        width = config.paper_width_px
        height = 2 * round(intrinsics.height_px * width / intrinsics.width_px / 2)
        intrinsics = intrinsics.resized(width, height)
        images = np.stack([cv2.resize(frame, (width, height), interpolation=cv2.INTER_AREA)
                           for frame in frames])
        cut = np.stack([cv2.resize(m.astype(np.float32), (width, height),
                                   interpolation=cv2.INTER_AREA) for m in masks_np]) >= 0.5
        viewport = Viewport.full_frame(intrinsics, len(frame_idx))
    camera = NadirCamera(intrinsics, torch.as_tensor(altitude, dtype=torch.float32),
                         refraction=config.use_refraction)
    data = FitData(frame_idx=frame_idx, time_s=clip.frame_time_s(frame_idx),
                   images=torch.as_tensor(images, dtype=torch.float32) / 255.0,
                   masks=torch.as_tensor(cut, dtype=torch.float32), camera=camera,
                   viewport=viewport, clip_focal_px=clip_focal_px,
                   warnings=tuple(warnings + altitude_warnings), animal_width_px=animal_width,
                   elongation=float(np.median([elongation(mask) for mask in masks_np])))
    data = replace(data, edge_blur_px=edge_blur_of(data))
    return data if factor == 1 else downscaled(data, factor, keep_area=True)


def _whole_frames(frame_idx: np.ndarray, masks: np.ndarray, altitude_m: np.ndarray,
                  focal_px: float) -> tuple[np.ndarray, list[str]]:
    """(T,) bool: the frames whose masks show the whole animal (``core.fit.whole_body``), all
    of them where none would be left; a warning naming those left out."""
    lengths_m = np.array([length_px(mask) for mask in masks]) * altitude_m / focal_px
    short = partial(lengths_m)
    if short.all() or not short.any():
        return np.ones(len(frame_idx), bool), []
    return ~short, [f"{int(short.sum())} frame(s) skipped: the mask is shorter than the animal "
                    f"is in the clip's other frames (diving, pitched or partly hidden: frames "
                    f"{list_some([str(int(t)) for t in frame_idx[short]])})"]


def fit_factor(width_px: float, config: FitConfig) -> int:
    """The power of two the crops are shrunk by for the fit: the largest that leaves the
    animal (``width_px`` wide at native resolution) at least ``config.fit_width_px`` wide
    (1 where that is 0)."""
    factor = 1
    while config.fit_width_px and width_px / (2 * factor) >= config.fit_width_px:
        factor *= 2
    return factor


def _masks_through_lens(clip: Clip, frame_idx: np.ndarray, masks: np.ndarray,
                        lens: LensModel) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """The chosen frames' masks undistorted, without those the undistortion pushes against
    the frame's edge or out of it (a barrel lens moves what lies near the edge outwards); a
    warning naming them, InputError when none is left."""
    undistorted = [lens.undistort_mask(mask) for mask in masks]
    kept = [t for t, mask in enumerate(undistorted) if mask.any() and not touches_border(mask)]
    dropped = [str(int(frame_idx[t])) for t in range(len(masks)) if t not in kept]
    if not kept:
        raise InputError(f"{clip.path}: through the lens model, the dolphin reaches the frame's "
                         f"edge in every chosen frame ({list_some(dropped)})")
    warnings = [f"{len(dropped)} frame(s) skipped: through the lens model the dolphin reaches "
                f"the frame's edge (frames {list_some(dropped)})"] if dropped else []
    return frame_idx[kept], np.stack([undistorted[t] for t in kept]), warnings


def _through_lens(read_frame: Callable[[int], np.ndarray],
                  lens: LensModel) -> Callable[[int], np.ndarray]:
    return lambda idx: lens.undistort_image(read_frame(idx))


def _read_frames(read_frame: Callable[[int], np.ndarray], frame_idx: np.ndarray,
                 total_steps: int, progress: ProgressCallback | None,
                 cancel: threading.Event | None) -> Iterator[np.ndarray]:
    """The frames in order, reading one at a time with a cancel check and a report each."""
    for count, idx in enumerate(frame_idx, start=1):
        check_cancel(cancel)
        frame = read_frame(int(idx))
        if progress is not None:
            progress(Progress(PREPARE_STAGE, 0, total_steps,
                              f"read frame {count} of {len(frame_idx)}"))
        yield frame


def _roi_windows(masks: np.ndarray, margin_px: int,
                 factor: int) -> tuple[np.ndarray, np.ndarray, int, int]:
    """Top-left corners (T,) and the common size of windows around every mask's box, whole
    multiples of ``factor`` times the alignments (so that a copy at 1/``factor`` of the
    resolution, and its coarse level, are exact)."""
    boxes = []
    for mask in masks:
        rows, cols = np.nonzero(mask)
        boxes.append((cols.min(), rows.min(), cols.max(), rows.max()))
    boxes = np.asarray(boxes)
    multiple, align = ROI_MULTIPLE_PX * factor, ROI_ALIGN_PX * factor
    width = _round_up(int((boxes[:, 2] - boxes[:, 0]).max()) + 1 + 2 * margin_px, multiple)
    height = _round_up(int((boxes[:, 3] - boxes[:, 1]).max()) + 1 + 2 * margin_px, multiple)
    centre_x = (boxes[:, 0] + boxes[:, 2]) / 2
    centre_y = (boxes[:, 1] + boxes[:, 3]) / 2
    x0 = np.floor(centre_x - (width - 1) / 2).astype(np.int64)
    y0 = np.floor(centre_y - (height - 1) / 2).astype(np.int64)
    return x0 - x0 % align, y0 - y0 % align, width, height


def _round_up(size: int, multiple: int) -> int:
    return int(math.ceil(size / multiple) * multiple)
