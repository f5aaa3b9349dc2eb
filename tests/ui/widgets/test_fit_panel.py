"""The fit panel: settings in and out, Start/Cancel, progress shown in words and numbers."""

from dolphinfit.core.progress import Progress
from dolphinfit.core.project.fit_settings import FitSettings
from dolphinfit.ui.widgets.fit_panel import FitPanel, format_eta


def test_settings_round_trip_and_start(qtbot):
    panel = FitPanel()
    qtbot.addWidget(panel)
    settings = FitSettings(start_s=1.0, end_s=4.5, fps=2.5, quality="quick", refraction=True,
                           roi=False)
    panel.set_settings(settings, duration_s=5.0)
    assert panel.settings() == settings
    panel.set_settings(FitSettings(), duration_s=5.0)
    assert panel.settings() == FitSettings()  # open ends shown as "from the start"/"to the end"
    assert panel.start_s.text() == "from the start"
    with qtbot.waitSignal(panel.start_requested, timeout=1000) as blocker:
        panel.start_button.click()
    assert blocker.args == [FitSettings()]
    panel.start_s.setValue(3.0)
    panel.end_s.setValue(2.0)
    panel.start_button.click()  # contradicting bounds: said in words, nothing started
    assert "must come after" in panel.status.text()


def test_progress_and_cancel(qtbot):
    panel = FitPanel()
    qtbot.addWidget(panel)
    panel.set_running(True)
    assert not panel.start_button.isEnabled() and panel.cancel_button.isEnabled()
    for step, loss in ((1, 2.0), (2, 1.0), (2, 1.0), (3, 0.5)):  # a repeated heartbeat
        panel.show_progress(Progress("global", step, 10, eta_s=65.0,
                                     metrics={"total": loss, "mean_iou": 0.8}))
    assert panel.loss_plot.values == [2.0, 1.0, 0.5]
    assert panel.progress_bar.value() == 3 and panel.progress_bar.maximum() == 10
    assert panel.progress_label.text() == "global · step 3 / 10 · ETA 1 min 05 s · mean IoU 0.800"
    with qtbot.waitSignal(panel.cancel_requested, timeout=1000):
        panel.cancel_button.click()
    panel.set_running(False)
    assert panel.start_button.isEnabled() and not panel.cancel_button.isEnabled()
    assert format_eta(None) == "" and format_eta(9.4) == "ETA 9 s"


def test_typed_range_is_checked_live_and_start_follows_the_masks(qtbot):
    """Each keystroke in the range reports the settings shown (before Enter stores them);
    Start stays off while the masks forbid it, also once a fit ends."""
    panel = FitPanel()
    qtbot.addWidget(panel)
    panel.set_settings(FitSettings(), duration_s=5.0)
    typed = []
    panel.range_typed.connect(typed.append)
    panel.end_s.setFocus()
    panel.end_s.selectAll()
    qtbot.keyClicks(panel.end_s, "2.5")
    assert typed[-1] == FitSettings(end_s=2.5)
    panel.show_mask_check("⚠ no usable masks in frames 0–24", False)
    assert not panel.start_button.isEnabled()
    assert panel.mask_note.isVisibleTo(panel) and panel.start_button.toolTip().startswith("⚠")
    panel.set_running(True)
    panel.set_running(False)
    assert not panel.start_button.isEnabled()
    panel.show_mask_check("", True)
    assert panel.start_button.isEnabled() and not panel.mask_note.isVisibleTo(panel)
