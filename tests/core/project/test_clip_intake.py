"""Adding a day's clips at once: each clip's SRT found and read, its camera guessed from its
size and the SRT's drone family, and each clip that cannot be used put aside with why."""

import shutil
from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.core.camera_presets import load_presets
from dolphinfit.core.io.srt import FAMILIES
from dolphinfit.core.project.clip_intake import guess_camera, intake, with_launch_height

DATA = Path(__file__).parents[2] / "data" / "srt"


def _video(path: Path, num_frames: int, fps: float = 10.0, size=(64, 48)) -> Path:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, size)
    for t in range(num_frames):
        writer.write(np.full((size[1], size[0], 3), 40 + 5 * t, np.uint8))
    writer.release()
    return path


def test_the_camera_is_the_one_preset_of_that_size_or_the_srt_family_decides():
    presets = load_presets()
    fhd = guess_camera(1920, 1080, None, presets)
    assert (fhd.preset_name, fhd.sure) == ("dji-mavic3-fhd", True)
    # two presets record 3840×2160: the SRT's family names the drone
    phantom = guess_camera(3840, 2160, FAMILIES["single-line"], presets)
    assert (phantom.preset_name, phantom.sure) == ("dji-phantom4pro-4k", True)
    mavic = guess_camera(3840, 2160, FAMILIES["modern"], presets)
    assert (mavic.preset_name, mavic.sure) == ("dji-mavic3-4k", True)
    unsure = guess_camera(3840, 2160, FAMILIES["m300"], presets)
    assert not unsure.sure and "check Clip → Camera" in unsure.why
    odd = guess_camera(640, 360, FAMILIES["modern"], presets)
    assert odd.preset_name is None and not odd.sure and odd.camera.image_width_px == 640


def test_each_clip_is_added_or_put_aside_with_its_reason(tmp_path):
    day = tmp_path / "day"
    day.mkdir()
    shutil.copy(_video(day / "DJI_0001.MP4", 20), day / "DJI_0010.MP4")
    shutil.copy(DATA / "MAVIC3.srt", day / "DJI_0001.SRT")           # relative altitude
    shutil.copy(DATA / "mavic_air2.srt", day / "DJI_0010.SRT")       # above the water
    _video(day / "DJI_0002.MP4", 20)                                  # no SRT
    _video(day / "DJI_0003.MP4", 5)                                   # half a second
    shutil.copy(DATA / "MAVIC3.srt", day / "DJI_0003.SRT")
    (day / "DJI_0004.MP4").write_bytes(b"not a video")                # unreadable
    shutil.copy(DATA / "MAVIC3.srt", day / "DJI_0004.SRT")
    _video(day / "DJI_0005.MP4", 20)
    (day / "DJI_0005.SRT").write_text("1\nthe card was full\n", encoding="utf-8")
    videos = sorted(day.glob("*.MP4"))
    reports = []
    found = intake(videos, tmp_path, known={"day/DJI_0010.MP4"}, progress=reports.append)
    assert [clip.entry.media_path for clip in found.clips] == ["day/DJI_0001.MP4"]
    refused = dict(line.split(": ", 1) for line in found.refused)
    assert refused.keys() == {"DJI_0002.MP4", "DJI_0003.MP4", "DJI_0004.MP4", "DJI_0005.MP4"}
    assert refused["DJI_0002.MP4"] == "no altitude: no DJI_0002.SRT beside it"
    assert refused["DJI_0003.MP4"].startswith("too short (5 frames, 0.5 s")
    assert "DJI_0005.SRT" in refused["DJI_0005.MP4"]
    assert [r.step for r in reports] == list(range(1, 7)) and reports[-1].total == 6
    clip = found.clips[0]
    assert clip.relative_altitude and clip.entry.altitude.path == "day/DJI_0001.SRT"
    assert clip.entry.altitude.source == "barometer"
    assert with_launch_height(clip, 1.5).altitude.launch_height_m == 1.5
    again = intake([day / "DJI_0010.MP4"], tmp_path)
    assert not again.clips[0].relative_altitude
    assert with_launch_height(again.clips[0], 1.5).altitude.launch_height_m == 0.0


def test_a_cancelled_intake_stops_between_clips(tmp_path):
    import threading

    from dolphinfit.core.progress import Cancelled
    for name in ("DJI_0001.MP4", "DJI_0002.MP4"):
        _video(tmp_path / name, 20)
    cancel, seen = threading.Event(), []

    def progress(report) -> None:  # the user cancels once the first clip is read
        seen.append(report.message)
        cancel.set()
    with pytest.raises(Cancelled):
        intake(sorted(tmp_path.glob("*.MP4")), tmp_path, progress=progress, cancel=cancel)
    assert seen == ["DJI_0001.MP4"]
