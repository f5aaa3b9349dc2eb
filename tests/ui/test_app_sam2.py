"""The Clip menu's SAM-2 back-end: disabled, saying why, where the sam2 package is missing; its
checkpoint asked for once and kept as a preference."""

import importlib.util

import pytest
from PySide6.QtWidgets import QFileDialog, QMessageBox

from dolphinfit.core.segment.backends import NETWORK, SAM2
from dolphinfit.ui.state.preferences import load_preferences

HAS_SAM2 = importlib.util.find_spec("sam2") is not None


@pytest.mark.skipif(HAS_SAM2, reason="the sam2 package is installed here")
def test_sam2_is_disabled_saying_why_without_its_package(make_window):
    action = make_window().actions_by_name["masks_sam2"]
    assert not action.isEnabled()
    assert "needs the 'sam2' package" in action.toolTip()
    assert "torchvision" in action.toolTip()


def test_sam2_asks_for_its_checkpoint_once_and_keeps_it(make_window, tmp_path, monkeypatch):
    checkpoint = tmp_path / "sam2.1_hiera_tiny.pt"
    checkpoint.write_bytes(b"")
    renamed = tmp_path / "my_model.pt"
    renamed.write_bytes(b"")
    answers, errors = ["", str(renamed), str(checkpoint)], []
    monkeypatch.setattr(QFileDialog, "getOpenFileName",
                        staticmethod(lambda *args, **kwargs: (answers.pop(0), "")))
    monkeypatch.setattr(QMessageBox, "warning", staticmethod(lambda *args: errors.append(args)))
    window = make_window()
    for _ in range(2):  # cancelled, then a checkpoint whose model cannot be told: no switch
        window._choose_mask_backend(SAM2)
        assert window.masks.backend == NETWORK
        assert window.actions_by_name["masks_network"].isChecked()
    assert "cannot tell the SAM-2 model" in errors[0][2]
    window._choose_mask_backend(SAM2)
    assert (window.masks.backend, window.masks.sam2_checkpoint) == (SAM2, checkpoint)
    assert window.actions_by_name["masks_sam2"].isChecked()
    window._choose_mask_backend(NETWORK)
    window._choose_mask_backend(SAM2)  # asked once: no answer is left to give
    assert not answers and window.masks.backend == SAM2
    prefs = load_preferences()
    assert (prefs["mask_backend"], prefs["sam2_checkpoint"]) == (SAM2, str(checkpoint))
    again = make_window()  # restored; SAM-2 itself only where its package is installed
    assert again.masks.sam2_checkpoint == checkpoint
    assert again.masks.backend == (SAM2 if HAS_SAM2 else NETWORK)
