"""From files to a fit: open the clip, read altitude and masks (or track them), prepare, fit.

One function for the CLI, the demo, the benchmarks and the GUI worker.
"""

import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from core.intrinsics import CameraIntrinsics
from core.camera_presets import DEFAULT_PRESET, get_preset
from core.errors import InputError
from core.fit.config import FitConfig
from core.fit.data import FitData, prepare_data
from core.fit.engine import FitProgress, fit
from core.fit.result import FitResult
from core.io.masks import MaskTrack, read_masks
from core.io.telemetry import Telemetry, load_telemetry
from core.io.video import Clip, VideoReader, open_clip
from core.segment.segmenter import AutoSeed
from core.segment.tracker import MaskTracker


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
                raise InputError("give both --sensor-width-mm and --focal-mm, or a --camera preset")
            return CameraIntrinsics.from_sensor(self.focal_mm, self.sensor_width_mm,
                                                clip.width_px, clip.height_px)
        preset = get_preset(self.preset or DEFAULT_PRESET)
        return CameraIntrinsics.from_sensor(preset.focal_mm, preset.sensor_width_mm,
                                            clip.width_px, clip.height_px)


@dataclass(frozen=True, eq=False)
class FitRun:
    """A finished fit with what it was fitted to."""

    clip: Clip
    telemetry: Telemetry
    masks: MaskTrack
    data: FitData
    result: FitResult


def run_fit(clip_path: Path, altitude: str | Path | float | None, masks_path: Path | None,
            camera: CameraChoice, config: FitConfig, launch_height_m: float = 0.0,
            progress: Callable[[FitProgress], None] | None = None,
            cancel: threading.Event | None = None) -> FitRun:
    """Fit the clip; without ``masks_path`` the built-in tracker finds the dolphin itself."""
    clip = open_clip(clip_path)
    telemetry = load_telemetry(clip, altitude, launch_height_m=launch_height_m)
    intrinsics = camera.intrinsics(clip)
    with VideoReader(clip) as frames:
        masks = (read_masks(masks_path, clip) if masks_path is not None
                 else MaskTracker().segment(frames, AutoSeed(frame_idx=0), cancel=cancel))
        data = prepare_data(clip, frames.frame, masks, telemetry, intrinsics, config)
    result = fit(data, config, progress=progress, cancel=cancel)
    return FitRun(clip=clip, telemetry=telemetry, masks=masks, data=data, result=result)
