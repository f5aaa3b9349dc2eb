"""From media to a fit: ``fit_clip`` prepares and fits an open clip with its telemetry and
masks (the GUI worker's entry); ``run_fit`` opens the files first and tracks the dolphin when
no masks are given (the CLI, the demo and the benchmarks).

Progress and cancel follow core.progress and core.fit.reporter; a cancel during the
optimisation returns the best state reached (``FitResult.status`` "cancelled"), one before it
raises core.progress.Cancelled. ``device`` (core.device) is where the fit and the edge
network compute; the data the run keeps stays on the CPU.
"""

import threading
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import torch

from dolphinfit.core.camera_presets import DEFAULT_PRESET, get_preset
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.data import FitData, prepare_data
from dolphinfit.core.fit.engine import fit
from dolphinfit.core.fit.result import FitResult
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.io.frame_source import FrameSource
from dolphinfit.core.io.masks import MaskTrack, read_masks
from dolphinfit.core.io.telemetry import Telemetry, load_telemetry
from dolphinfit.core.io.video import Clip, VideoReader, open_clip
from dolphinfit.core.measure.altitude_calibration import AltitudeCalibration, calibrated_telemetry
from dolphinfit.core.measure.lens import LensModel
from dolphinfit.core.progress import ProgressCallback
from dolphinfit.core.scan.clip_scan import scan_telemetry
from dolphinfit.core.scan.fit_seed import scan_pick
from dolphinfit.core.scan.scanner import Scanner
from dolphinfit.core.segment.auto_seed import DOLPHIN_LENGTH_M, expected_length_px
from dolphinfit.core.segment.backends import DEFAULT_BACKEND, make_segmenter
from dolphinfit.core.segment.net_tracker import NetTracker
from dolphinfit.core.segment.segmenter import AutoSeed, Seed

@dataclass(frozen=True)
class CameraChoice:
    """A preset name, or an explicit sensor width and focal length (mm)."""

    preset: str | None = None
    sensor_width_mm: float | None = None
    focal_mm: float | None = None

    def intrinsics(self, clip: Clip) -> CameraIntrinsics:
        """Full-frame intrinsics for the clip's frame size."""
        if self.sensor_width_mm is not None or self.focal_mm is not None:
            if self.sensor_width_mm is None or self.focal_mm is None:
                raise InputError("camera: give both the sensor width and the focal length (mm), "
                                 "or a camera preset")
            return CameraIntrinsics.from_sensor(self.focal_mm, self.sensor_width_mm,
                                                clip.width_px, clip.height_px)
        preset = get_preset(self.preset or DEFAULT_PRESET)
        return CameraIntrinsics.from_sensor(preset.focal_mm, preset.sensor_width_mm,
                                            clip.width_px, clip.height_px)

    def is_approximate(self, clip: Clip) -> bool:
        """Whether the focal length is unverified for the clip's video mode: a preset marked
        approximate, or a preset taken to another frame size than its own (the mode may crop
        the sensor), as the app has it (core.project.clip_cameras); explicit values count as
        calibrated."""
        if self.sensor_width_mm is not None and self.focal_mm is not None:
            return False
        preset = get_preset(self.preset or DEFAULT_PRESET)
        return preset.approximate or (preset.image_width_px, preset.image_height_px) != (
            clip.width_px, clip.height_px)


@dataclass(frozen=True, eq=False)
class FitRun:
    """A finished fit with what it was fitted to."""

    clip: Clip
    telemetry: Telemetry
    masks: MaskTrack
    data: FitData
    result: FitResult


def fit_clip(frames: FrameSource, telemetry: Telemetry, masks: MaskTrack,
             intrinsics: CameraIntrinsics, config: FitConfig,
             progress: ProgressCallback | None = None,
             cancel: threading.Event | None = None, lens: LensModel | None = None,
             device: torch.device | str = "cpu") -> FitRun:
    """Fit the clip of ``frames`` (full-frame ``intrinsics``) to its masks, through ``lens``
    where given (the run keeps the masks as they were tracked), on ``device``."""
    data = prepare_data(frames.clip, frames.frame, masks, telemetry, intrinsics, config,
                        progress=progress, cancel=cancel, lens=lens)
    result = fit(data, config, progress=progress, cancel=cancel, device=device)
    result = replace(result, edge_blur_px=data.edge_blur_px)
    return FitRun(clip=frames.clip, telemetry=telemetry, masks=masks, data=data, result=result)


def sized_auto_seed(frame_idx: int, intrinsics: CameraIntrinsics,
                    telemetry: Telemetry) -> AutoSeed:
    """The automatic seed in ``frame_idx`` looking for an animal ``DOLPHIN_LENGTH_M`` long at
    the clip's altitudes (``expected_length_px``)."""
    return AutoSeed(frame_idx, expected_length_px(intrinsics.focal_px, telemetry.altitude_m,
                                                  DOLPHIN_LENGTH_M))


def scanned_seed(frames: FrameSource, telemetry: Telemetry, intrinsics: CameraIntrinsics,
                 config: FitConfig, seed: AutoSeed, progress: ProgressCallback | None,
                 cancel: threading.Event | None,
                 scanner: Scanner | None = None) -> tuple[Seed, str]:
    """The scan's pick over the fit's window as a click (core.scan.fit_seed), with its line
    for the user; where the scan keeps no animal, ``seed`` sized by the camera
    (``sized_auto_seed``), which looks frame by frame. ``scanner``: one whose network the
    tracker shares (default: a new one)."""
    pick = scan_pick(frames, scan_telemetry(frames.clip, telemetry, intrinsics.focal_px),
                     (config.start_s, config.end_s), scanner, progress=progress,
                     cancel=cancel)
    if pick is not None:
        return pick.seed, pick.line
    sized = seed if seed.length_px is not None else \
        sized_auto_seed(seed.frame_idx, intrinsics, telemetry)
    return sized, "the scan kept no animal seen in two of its samples"


def run_fit(clip_path: Path, altitude: str | Path | float | None, masks_path: Path | None,
            camera: CameraChoice, config: FitConfig, launch_height_m: float = 0.0,
            progress: ProgressCallback | None = None,
            cancel: threading.Event | None = None, seed: Seed = AutoSeed(frame_idx=0),
            time_offset_s: float = 0.0, backend: str = DEFAULT_BACKEND,
            altitude_calibration: AltitudeCalibration | None = None,
            also_frames: Sequence[int] = (), lens: LensModel | None = None,
            device: torch.device | str = "cpu") -> FitRun:
    """Fit the clip; without ``masks_path`` the mask ``backend`` (core.segment.backends)
    finds the dolphin from ``seed`` on the frames the fit will look at and on
    ``also_frames`` (e.g. the frames measured by the elliptical method), reporting its own
    "track" stage first. An automatic seed is the animal a scan of the fit's window follows
    longest (``scanned_seed``), the masks' source naming it. An ``altitude_calibration`` of
    the clip's camera corrects the altitudes first; a ``lens`` of its video mode undistorts
    the frames and masks the fit sees. The fit and the mask back-end's networks run on
    ``device`` (the salient network and the scan on the CPU)."""
    clip = open_clip(clip_path)
    telemetry = load_telemetry(clip, altitude, launch_height_m, time_offset_s)
    intrinsics = camera.intrinsics(clip)
    if altitude_calibration is not None:
        altitude_calibration.check_focal_px(intrinsics.focal_px, str(clip_path))
        telemetry = calibrated_telemetry(telemetry, altitude_calibration)
    # frames are read in order by the tracker and once more by the preparation: a frame cache
    # would only hold memory through the long optimisation
    with VideoReader(clip, cache_bytes=0) as frames:
        if masks_path is not None:
            masks = read_masks(masks_path, clip)
        else:
            tracked = sorted({*map(int, config.frames_of(clip)), *map(int, also_frames)})
            note = None
            segmenter = make_segmenter(backend, only_frames=tracked, device=device)
            if isinstance(seed, AutoSeed):
                # the network tracker's salient network scans too: loaded once
                scanner = (Scanner(net=segmenter.look.net) if isinstance(segmenter, NetTracker)
                           else None)
                seed, note = scanned_seed(frames, telemetry, intrinsics, config, seed,
                                          progress, cancel, scanner)
            masks = segmenter.segment(frames, seed, progress=progress, cancel=cancel)
            if note is not None:
                masks = replace(masks, source=f"{masks.source}; {note}")
        return fit_clip(frames, telemetry, masks, intrinsics, config, progress, cancel, lens,
                        device)
