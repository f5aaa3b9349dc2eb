"""GUI tests: the user's config folder (camera presets, recent files, preferences) is a
temporary one, so tests never read or write the real one."""

import gc
from pathlib import Path

import pytest

from dolphinfit.core.camera_presets import DEFAULT_PRESET, get_preset
from dolphinfit.core.project.model import AltitudeSpec

from ..core.io.exif_still import write_still
from .ellipse_scene import dolphin_frame


@pytest.fixture(autouse=True)
def config_dir(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch):
    path = tmp_path_factory.mktemp("config")
    monkeypatch.setenv("DOLPHINFIT_CONFIG_DIR", str(path))
    return path


@pytest.fixture(autouse=True)
def no_modal_dialogs(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """A modal message box or file dialog would wait for a click forever: fail instead.

    Tests that expect one replace the method they expect with their own answer.
    """
    from PySide6.QtWidgets import QFileDialog, QInputDialog, QMessageBox

    def refuse(name: str):
        def modal(*args, **kwargs):
            texts = [a for a in args if isinstance(a, str)]
            raise AssertionError(f"unexpected modal {name}: {texts}")
        return modal

    for cls, names in ((QMessageBox, ("warning", "question", "information", "critical",
                                      "about")),
                       (QFileDialog, ("getOpenFileName", "getOpenFileNames",
                                      "getSaveFileName", "getExistingDirectory")),
                       (QInputDialog, ("getInt", "getText", "getDouble", "getItem"))):
        for name in names:
            monkeypatch.setattr(cls, name, staticmethod(refuse(f"{cls.__name__}.{name}")))
    return []


@pytest.fixture(scope="session", autouse=True)
def collect_on_the_gui_thread(qapp):
    """As the app does (ui/gc_guard.py): no cycle collection in worker threads."""
    from dolphinfit.ui.gc_guard import GuiThreadGarbageCollector
    collector = GuiThreadGarbageCollector(qapp)
    yield collector
    collector.stop()


@pytest.fixture(autouse=True)
def collect_after_each_test():
    """Each test's garbage is collected here, on the GUI thread, before the next test."""
    yield
    gc.collect()


@pytest.fixture
def shown_canvas(qtbot):
    """Makes a FrameCanvas of a given size showing a frame."""
    from dolphinfit.ui.widgets.canvas import FrameCanvas

    def make(frame, size: tuple[int, int]) -> FrameCanvas:
        view = FrameCanvas()
        qtbot.addWidget(view)
        view.resize(*size)
        view.show()
        qtbot.waitExposed(view)
        view.set_frame(frame)
        return view

    return make


@pytest.fixture
def make_window(qtbot):
    """Makes shown, active main windows that close without asking about unsaved work (a test
    that cares overrides ``ask.save_changes``); every worker stops after the test."""
    from dolphinfit.ui.main_window import MainWindow

    windows = []

    def make(size: tuple[int, int] = (1500, 950)) -> MainWindow:
        window = MainWindow()
        window.ask.save_changes = lambda: "discard"
        qtbot.addWidget(window)
        window.resize(*size)
        window.show()
        qtbot.waitExposed(window)
        window.activateWindow()
        qtbot.waitActive(window)  # window shortcuts fire only in the active window
        windows.append(window)
        return window

    yield make
    for window in windows:
        window.shutdown()  # also for a window a test left open with unsaved work
        window.model.undo_stack.clear()


STILL_ALTITUDE_M = 20.0   # what opening the still answers for its altitude


@pytest.fixture
def still(tmp_path: Path) -> Path:
    """The ellipse scene as a PNG still in a survey folder, whose EXIF names a camera of the
    default preset's focal length and sensor width (a still's camera is its EXIF's)."""
    path = tmp_path / "survey" / "DJI_0001.png"
    path.parent.mkdir()
    frame, preset = dolphin_frame(), get_preset(DEFAULT_PRESET)
    return write_still(path, frame, preset.focal_mm, preset.sensor_width_mm / frame.shape[1])


@pytest.fixture
def new_window(make_window):
    """Makes main windows that close without asking (a test that cares overrides it) and
    answer the altitude question that opening new media asks with a constant 20 m."""
    def make():
        window = make_window((1400, 900))
        # what the altitude dialog returns for a constant (the dialog is tested on its own)
        window.ask.altitude = lambda *asked: AltitudeSpec(constant_m=STILL_ALTITUDE_M,
                                                          source="laser")
        return window

    return make
