"""Telemetry files of a synthetic clip: the altitude CSV and a DJI-style SRT sidecar.

The SRT follows the modern DJI family (Mavic 3; reference/ecosystem.md): one cue per frame
with ``FrameCnt``, ``DiffTime``, a local timestamp and a bracket line whose ``rel_alt`` is the
height above the take-off point (altitude above the water minus the launch height) and whose
``focal_len`` is the 35 mm-equivalent value (never a metric focal length).
"""

from datetime import datetime, timedelta
from pathlib import Path

import numpy as np

from dolphinfit.core.io.altitude_csv import write_altitude_csv
from dolphinfit.core.io.atomic import atomic_path

SRT_START = datetime(2024, 6, 1, 9, 30, 0)   # a fixed, plausible recording time
SRT_LATITUDE = -25.78                         # Shark Bay, Western Australia (the paper's site)
SRT_LONGITUDE = 113.72
SEA_LEVEL_ABS_ALT_M = 0.0


def write_altitude(path: Path, time_s: np.ndarray, altitude_m: np.ndarray) -> None:
    """``frame,time_s,altitude_m`` CSV, one row per frame."""
    write_altitude_csv(path, {"frame": np.arange(len(time_s)), "time_s": time_s,
                              "altitude_m": altitude_m})


def _srt_time(seconds: float) -> str:
    millis = int(round(seconds * 1000))
    hours, rest = divmod(millis, 3_600_000)
    minutes, rest = divmod(rest, 60_000)
    return f"{hours:02d}:{minutes:02d}:{rest // 1000:02d},{rest % 1000:03d}"


def write_dji_srt(path: Path, time_s: np.ndarray, altitude_m: np.ndarray, fps: float,
                  launch_height_m: float) -> None:
    """A per-frame DJI modern-family SRT with rel_alt = altitude − launch height."""
    step = 1.0 / fps
    cues = []
    for index, (t, altitude) in enumerate(zip(time_s, altitude_m)):
        stamp = SRT_START + timedelta(seconds=float(t))
        cues.append(
            f"{index + 1}\n{_srt_time(t)} --> {_srt_time(t + step)}\n"
            f'<font size="28">FrameCnt: {index + 1}, DiffTime: {int(round(step * 1000))}ms\n'
            f"{stamp:%Y-%m-%d %H:%M:%S}.{stamp.microsecond // 1000:03d}\n"
            f"[iso: 100] [shutter: 1/1000.0] [fnum: 2.8] [ev: 0] [ct: 5600] "
            f"[color_md : default] [focal_len: 24.00] [latitude: {SRT_LATITUDE:.5f}] "
            f"[longitude: {SRT_LONGITUDE:.5f}] [rel_alt: {altitude - launch_height_m:.3f} "
            f"abs_alt: {altitude + SEA_LEVEL_ABS_ALT_M:.3f}] </font>\n")
    with atomic_path(path) as tmp:
        tmp.write_text("\n".join(cues), encoding="utf-8")
