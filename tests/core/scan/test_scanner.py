"""The scanner's schedule on a drawn clip with a stand-in for the network (dark pixels are
salient): the frame searched in tiles at the start, each animal followed between, and an
animal that comes into view found at the next look at the whole frame, not at the next
search in tiles."""

from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.core.io.frame_source import Clip
from dolphinfit.core.scan.clip_scan import ClipTelemetry
from dolphinfit.core.scan.frame_scores import ScanSettings
from dolphinfit.core.scan.scanner import Scanner

FPS, SECONDS, WIDTH, HEIGHT = 2.0, 20, 480, 320
ARRIVES_S = 7.0   # the second animal comes into view then


class DrawnClip:
    """Water with a dark elongated animal swimming right, and from ARRIVES_S a second."""

    clip = Clip(Path("drawn.mp4"), FPS, int(FPS * SECONDS), WIDTH, HEIGHT)

    def __getitem__(self, frame_idx: int) -> np.ndarray:
        t = frame_idx / FPS
        frame = np.full((HEIGHT, WIDTH, 3), (40, 110, 120), np.uint8)
        cv2.ellipse(frame, (int(80 + 8 * t), 100), (45, 9), 0, 0, 360, (30, 30, 30), -1)
        if t >= ARRIVES_S:
            cv2.ellipse(frame, (int(380 - 6 * t), 230), (40, 8), 10, 0, 360, (30, 30, 30), -1)
        return frame


class DarkIsSalient:
    """The network's stand-in: saliency 1 on dark pixels; counts its looks by window size."""

    def __init__(self) -> None:
        self.looks: list[tuple[int, int]] = []

    def saliency(self, crop_rgb: np.ndarray) -> np.ndarray:
        self.looks.append(crop_rgb.shape[:2])
        return (crop_rgb.mean(axis=2) < 60).astype(np.float32)


def test_an_animal_coming_into_view_is_found_at_the_next_look_at_the_whole_frame():
    net = DarkIsSalient()
    frames = DrawnClip()
    nothing = np.full(frames.clip.num_frames, np.nan)
    scan = Scanner(net=net).scan(frames, ClipTelemetry(None, nothing, nothing),
                                 ScanSettings(sample_fps=1.0, search_every_s=5.0,
                                              tile_search_every_s=15.0))
    assert scan.animal_ids() == [1, 2]
    first, second = scan.of_animal(1), scan.of_animal(2)
    assert len(first) == 20  # followed in every sample
    # in view from 7 s: found by the look at the whole frame at 10 s (the tiles wait for 15 s)
    assert second[0].frame_idx == 20 and second[-1].frame_idx == 38
    # the whole frame looked at by the searches in tiles at 0 and 15 s and the glances at
    # 5 and 10 s
    assert net.looks.count((HEIGHT, WIDTH)) == 4


def test_the_fits_automatic_seed_takes_the_animal_seen_longest_in_its_window():
    """Over the whole clip the first animal is seen in all 20 samples and the newcomer in 10:
    the fit takes the first, at its centre in one of its frames, and the line names both.
    From 12 to 16 s both are seen in all 4 samples: the tie goes to the one nearer the
    frame's middle. Plain water: no pick (the fit falls back on the one-frame seed)."""
    from dolphinfit.core.scan.fit_seed import scan_pick

    frames = DrawnClip()
    nothing = np.full(frames.clip.num_frames, np.nan)
    telemetry = ClipTelemetry(None, nothing, nothing)
    pick = scan_pick(frames, telemetry, (None, None), Scanner(net=DarkIsSalient()))
    assert pick.animal_id == 1
    t = pick.seed.frame_idx / FPS
    assert pick.seed.x_px == pytest.approx(80 + 8 * t, abs=2) and pick.seed.y_px == \
        pytest.approx(100, abs=1)
    assert "scan of 20 frames: 2 animals kept; took dolphin 1 seen in 20 of 20" in pick.line
    assert "also dolphin 2 seen in 10 of 20 samples" in pick.line
    late = scan_pick(frames, telemetry, (12.0, 16.0), Scanner(net=DarkIsSalient()))
    assert late.line.startswith("scan of 4 frames: 2 animals kept; took dolphin 1 seen in 4")
    assert late.seed.y_px == pytest.approx(100, abs=1)
    assert 24 <= late.seed.frame_idx < 32

    class Water(DrawnClip):
        def __getitem__(self, frame_idx: int) -> np.ndarray:
            return np.full((HEIGHT, WIDTH, 3), (40, 110, 120), np.uint8)

    assert scan_pick(Water(), telemetry, (None, None), Scanner(net=DarkIsSalient())) is None


def test_on_a_tie_the_fit_takes_the_animal_in_the_middle_of_the_frame():
    """A pair seen in every sample: the larger animal swims near the frame's corner, the one
    the pilot films in its middle; the fit takes the middle one, and the line names both."""
    from dolphinfit.core.scan.fit_seed import scan_pick

    class FilmedPair(DrawnClip):
        def __getitem__(self, frame_idx: int) -> np.ndarray:
            t = frame_idx / FPS
            frame = np.full((HEIGHT, WIDTH, 3), (40, 110, 120), np.uint8)
            cv2.ellipse(frame, (int(90 + 2 * t), 60), (60, 12), 0, 0, 360, (30, 30, 30), -1)
            cv2.ellipse(frame, (int(230 + 2 * t), 170), (40, 8), 0, 0, 360, (30, 30, 30), -1)
            return frame

    nothing = np.full(FilmedPair.clip.num_frames, np.nan)
    pick = scan_pick(FilmedPair(), ClipTelemetry(None, nothing, nothing), (None, None),
                     Scanner(net=DarkIsSalient()))
    assert pick.seed.y_px == pytest.approx(170, abs=1)
    assert "2 animals kept" in pick.line and "seen in 20 of 20 samples" in pick.line
