"""FrameLoader serves the newest request from a worker thread; rgb_to_qimage copies."""

import threading
import time
from pathlib import Path

import numpy as np
import pytest
from PySide6.QtCore import QThread

from dolphinfit.core.io.video import Clip
from dolphinfit.ui.workers.frame_loader import FrameLoader, rgb_to_qimage

TIMEOUT_MS = 5000


class SlowSource:
    """Frame k is filled with k; each decode takes 50 ms and is recorded with its thread."""

    def __init__(self, num_frames: int = 40, fail_at: int | None = None) -> None:
        self.clip = Clip(Path("fake.mp4"), 25.0, num_frames, 8, 6)
        self.decoded: list[int] = []
        self.threads: set[threading.Thread] = set()
        self._fail_at = fail_at

    def frame(self, frame_idx: int) -> np.ndarray:
        self.threads.add(threading.current_thread())
        time.sleep(0.05)
        if frame_idx == self._fail_at:
            raise OSError(f"frame {frame_idx} is damaged")
        self.decoded.append(frame_idx)
        rgb = np.full((6, 8, 3), frame_idx, dtype=np.uint8)
        rgb.flags.writeable = False
        return rgb


@pytest.fixture
def loader(qtbot):
    frame_loader = FrameLoader()
    yield frame_loader
    frame_loader.shutdown()


def test_a_burst_of_requests_decodes_few_frames_and_delivers_the_newest_last(qtbot, loader):
    source = SlowSource()
    loader.set_source(source)
    delivered: list[tuple[int, np.ndarray, QThread]] = []
    loader.frame_ready.connect(
        lambda idx, rgb: delivered.append((idx, rgb, QThread.currentThread())))
    with qtbot.waitSignal(loader.frame_ready, timeout=TIMEOUT_MS,
                          check_params_cb=lambda idx, rgb: idx == 30):
        for idx in range(31):
            loader.request(idx)
    with qtbot.assertNotEmitted(loader.frame_ready, wait=150):
        pass
    assert delivered[-1][0] == 30
    assert len(source.decoded) <= 3
    assert source.decoded[-1] == 30
    assert threading.main_thread() not in source.threads
    for idx, rgb, thread in delivered:
        assert thread is loader.thread()  # delivered on the GUI thread
        assert rgb.shape == (6, 8, 3) and (rgb == idx).all()


def test_an_exception_from_the_source_is_reported_as_failed(qtbot, loader):
    loader.set_source(SlowSource(fail_at=3))
    with qtbot.waitSignal(loader.failed, timeout=TIMEOUT_MS) as blocker:
        loader.request(3)
    assert blocker.args == [3, "frame 3 is damaged"]
    with qtbot.waitSignal(loader.frame_ready, timeout=TIMEOUT_MS) as blocker:
        loader.request(4)  # the worker survives the error
    assert blocker.args[0] == 4


def test_results_of_a_replaced_source_are_dropped(qtbot, loader):
    old, new = SlowSource(), SlowSource()
    loader.set_source(old)
    loader.request(5)
    loader.set_source(new)
    with qtbot.waitSignal(loader.frame_ready, timeout=TIMEOUT_MS) as blocker:
        loader.request(7)
    assert blocker.args[0] == 7
    assert new.decoded == [7]


def test_shutdown_joins_the_thread_and_later_requests_are_ignored(qtbot):
    frame_loader = FrameLoader()
    source = SlowSource()
    frame_loader.set_source(source)
    frame_loader.request(1)
    frame_loader.shutdown()
    assert frame_loader._thread.isFinished()
    frame_loader.set_source(source)
    frame_loader.request(2)
    with qtbot.assertNotEmitted(frame_loader.frame_ready, wait=150):
        pass
    assert 2 not in source.decoded


def test_rgb_to_qimage_copies_a_read_only_frame():
    wide = np.zeros((5, 14, 3), dtype=np.uint8)
    wide[2, 6] = (10, 20, 30)
    wide.flags.writeable = False
    image = rgb_to_qimage(wide[:, ::2])  # a non-contiguous, read-only view
    assert (image.width(), image.height()) == (7, 5)
    assert image.pixelColor(3, 2).getRgb()[:3] == (10, 20, 30)
    assert image.bytesPerLine() >= 21
    with pytest.raises(ValueError):
        rgb_to_qimage(np.zeros((5, 7), dtype=np.uint8))
