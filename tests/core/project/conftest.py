"""A small project built in code: a 1280×720 clip entry with one animal and an elliptical
dolphin measured on frame 3 (midline along the major axis, edges on the outline)."""

import cv2
import numpy as np
import pytest

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.measure.annotation import place_stations
from dolphinfit.core.measure.stations import NUM_STATIONS
from dolphinfit.core.project.fit_settings import FitSettings
from dolphinfit.core.project.model import AltitudeSpec, Animal, ClipEntry, Measurement, Project

CENTRE = np.array([640.0, 360.0])
SEMI_MAJOR, SEMI_MINOR = 300.0, 50.0
ANGLE = np.deg2rad(15.0)


def ellipse_measurement(frame_idx: int = 3, scale: float = 1.0) -> Measurement:
    """The midline along the major axis (3 clicks) and each station's edges on the outline."""
    axis = np.array([np.cos(ANGLE), np.sin(ANGLE)])
    a = SEMI_MAJOR * scale
    midline = CENTRE + np.outer([-a, 0.0, a], axis)
    stations = place_stations(midline)
    along = (stations.points_px - CENTRE) @ axis
    half = SEMI_MINOR * scale * np.sqrt(1 - (along / a) ** 2)
    return Measurement(frame_idx=frame_idx, midline_px=midline,
                       offsets_px=np.stack([half, -half], axis=1))


def write_black_clip(folder) -> None:
    """The project's clip (``clip.mp4``, 10 black 1280×720 frames at 10 fps) in ``folder``."""
    folder.mkdir()
    writer = cv2.VideoWriter(str(folder / "clip.mp4"), cv2.VideoWriter_fourcc(*"mp4v"), 10.0,
                             (1280, 720))
    for _ in range(10):
        writer.write(np.zeros((720, 1280, 3), np.uint8))
    writer.release()


@pytest.fixture
def camera() -> CameraPreset:
    return CameraPreset(name="test", description="test camera", focal_mm=12.29,
                        sensor_width_mm=17.27, image_width_px=1280, image_height_px=720,
                        source="test", approximate=False)


@pytest.fixture
def project(camera: CameraPreset) -> Project:
    animal = Animal("dolphin 1", notes="scar on the dorsal fin",
                    measurements=(ellipse_measurement(3), ellipse_measurement(7, 1.02)),
                    fit_settings=FitSettings(start_s=0.5, end_s=4.0, fps=2.5, quality="quick"),
                    fit_path="p.fits/clip_dolphin-1")
    clip = ClipEntry(media_path="media/clip.mp4", kind="video", camera=camera,
                     altitude=AltitudeSpec(constant_m=18.0, source="laser"),
                     animals=(animal, Animal("dolphin 2")), masks_path="media/masks",
                     scan_path="p.scans/clip_scan.json", rejected_frames=((2, 40), (1, 10)))
    return Project(clips=(clip,))


__all__ = ["NUM_STATIONS"]
