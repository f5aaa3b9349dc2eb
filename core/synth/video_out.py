"""A synthetic clip's video file: FFV1 (lossless) or mp4v through OpenCV, or H.264 through
PyAV's libx264 at a drone's bit rate or a constant rate factor (OpenCV's wheels cannot encode
H.264)."""

from fractions import Fraction
from pathlib import Path
from typing import Protocol

import av
import cv2
import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import LOSSLESS_CODEC

H264_PRESET = "medium"


class ClipWriter(Protocol):
    """Takes (H, W, 3) uint8 BGR frames in order; ``close`` finishes the file."""

    def write(self, frame: np.ndarray) -> None: ...

    def close(self) -> None: ...


class _OpenCVWriter:
    def __init__(self, path: Path, codec: str, config: SynthConfig):
        self.writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*codec), config.fps,
                                      (config.width_px, config.height_px))
        if not self.writer.isOpened():
            raise InputError(f"{path}: OpenCV cannot write {codec} video here")

    def write(self, frame: np.ndarray) -> None:
        self.writer.write(frame)

    def close(self) -> None:
        self.writer.release()


class _H264Writer:
    def __init__(self, path: Path, config: SynthConfig):
        self.container = av.open(str(path), mode="w")
        rate = {} if config.crf is None else {"crf": str(config.crf)}
        self.stream = self.container.add_stream(
            "libx264", rate=Fraction(config.fps).limit_denominator(1001),
            options={"preset": H264_PRESET, **rate})
        self.stream.width, self.stream.height = config.width_px, config.height_px
        self.stream.pix_fmt = "yuv420p"
        if config.crf is None:
            self.stream.bit_rate = int(config.bitrate_mbps * 1e6)

    def write(self, frame: np.ndarray) -> None:
        picture = av.VideoFrame.from_ndarray(np.ascontiguousarray(frame), format="bgr24")
        for packet in self.stream.encode(picture):
            self.container.mux(packet)

    def close(self) -> None:
        for packet in self.stream.encode():
            self.container.mux(packet)
        self.container.close()


def open_clip_writer(path: Path, config: SynthConfig) -> ClipWriter:
    """The writer of ``config``'s video at ``path`` (its folder made first)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not config.effects.compression:
        return _OpenCVWriter(path, LOSSLESS_CODEC[0], config)
    if config.codec == "h264":
        return _H264Writer(path, config)
    return _OpenCVWriter(path, config.codec, config)
