"""Edit → Compute device: CUDA offered only where torch sees a GPU (saying why not elsewhere,
without loading torch on the GUI thread), the choice kept as a preference and handed to the
fits and the tracker."""

import pytest

from dolphinfit.ui import main_window
from dolphinfit.ui.main_window import CUDA_CHECKING
from dolphinfit.ui.state.preferences import load_preferences, save_preference


@pytest.fixture
def window_seeing(make_window, qtbot, monkeypatch):
    """A window whose probe finds a CUDA GPU or not, once the probe has answered."""
    def make(gpu: bool):
        monkeypatch.setattr(main_window, "cuda_available", lambda: gpu)
        window = make_window()
        cuda = window.actions_by_name["device_cuda"]
        qtbot.waitUntil(lambda: cuda.toolTip() != CUDA_CHECKING, timeout=30_000)
        return window
    return make


def _jobs_device(window) -> tuple[str, str]:
    return window.fits.device, window.masks.device


def test_without_a_gpu_cuda_is_disabled_saying_why(window_seeing):
    window = window_seeing(False)
    cuda = window.actions_by_name["device_cuda"]
    assert not cuda.isEnabled()
    assert "torch sees no CUDA GPU" in cuda.toolTip() and "CUDA build" in cuda.toolTip()
    assert window.actions_by_name["device_auto"].isChecked()
    assert _jobs_device(window) == ("auto", "auto")


def test_the_choice_reaches_the_jobs_and_is_kept(window_seeing):
    window = window_seeing(True)
    assert window.actions_by_name["device_cuda"].isEnabled()
    window.actions_by_name["device_cuda"].trigger()
    assert _jobs_device(window) == ("cuda", "cuda")
    window.actions_by_name["device_cpu"].trigger()
    assert _jobs_device(window) == ("cpu", "cpu")
    assert load_preferences()["compute_device"] == "cpu"
    again = window_seeing(True)
    assert again.actions_by_name["device_cpu"].isChecked()
    assert _jobs_device(again) == ("cpu", "cpu")


def test_a_kept_cuda_choice_computes_on_auto_where_the_gpu_is_gone(window_seeing):
    """The jobs compute where auto finds (the CPU); the choice stays for when the GPU is
    back."""
    save_preference("compute_device", "cuda")
    window = window_seeing(False)
    assert window.actions_by_name["device_auto"].isChecked()
    assert _jobs_device(window) == ("auto", "auto")
    assert load_preferences()["compute_device"] == "cuda"
    assert _jobs_device(window_seeing(True)) == ("cuda", "cuda")
