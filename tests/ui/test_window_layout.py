"""The window's layout at the sizes people work at, on the sample project with its dolphin
measured: the 3D view's tab, added with a fit, keeps the video's size and the animal's
figures in sight; the Project dock shows each clip's status whole; the Frames dock lists a
scan without scrolling sideways, with more of its columns once widened."""

from dataclasses import replace

import pytest
from PySide6.QtCore import QRect, Qt
from PySide6.QtWidgets import QGroupBox, QWidget

from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.measure.mask_midline import midline_from_mask
from dolphinfit.core.project.sample import ensure_sample_project
from dolphinfit.core.project.scan_store import ClipStatus
from dolphinfit.ui.state.commands import edit_measurement

MEASURED_FRAME = 24   # the sample dolphin lies flat and whole in the frame here
SIZES = [(1600, 1000), (1920, 1080)]
WIDE_DOCK_PX = 700


@pytest.fixture
def sample_window(qtbot, make_window, tmp_path):
    """Makes a window of a given size on a copy of the sample project (saved into a
    temporary folder first, so that no autosave of it lands beside the shared sample), its
    dolphin measured on MEASURED_FRAME from the mask (length and suggested edges), the
    results shown."""
    def make(size: tuple[int, int]):
        window = make_window(size)
        assert (window.width(), window.height()) == size
        with qtbot.waitSignal(window.state.session_opened, timeout=30_000):
            window.files.open_path(ensure_sample_project())
        assert window.files.save(tmp_path / f"sample_{size[0]}.dolphinfit")
        with qtbot.waitSignal(window.state.frame_shown, timeout=10_000):
            window.go_to_frame(MEASURED_FRAME)
        window.on_measure_frame()
        model = window.model
        mask = read_masks(model.path.parent / model.project.clips[0].masks_path).mask(
            MEASURED_FRAME)
        edit_measurement(model, model.current_key(), replace(
            model.current_measurement(), midline_px=midline_from_mask(mask)), "length")
        window.overlay.suggest_edges(mask)
        qtbot.waitUntil(lambda: window.results.current_result() is not None
                        and window.results.current_result().estimate.interval is not None,
                        timeout=60_000)
        return window

    return make


def _animal_box(window) -> QGroupBox:
    return next(box for box in window.results.findChildren(QGroupBox)
                if box.title() == "Animal over its frames")


def _in_sight(widget: QWidget, window) -> bool:
    """Shown, whole (not scrolled or tabbed out of view) and inside the window."""
    place = QRect(widget.mapTo(window, widget.rect().topLeft()), widget.size())
    return (widget.isVisible() and widget.visibleRegion().boundingRect() == widget.rect()
            and window.rect().contains(place))


@pytest.mark.parametrize("size", SIZES)
def test_the_3d_view_keeps_the_video_and_the_animals_figures(qtbot, sample_window, size):
    """With a fit shown the 3D view's tab joins the results: the canvas shrinks < 5 % (it
    lost a fifth when the view took the right-hand column) and 'Animal over its frames'
    stays whole in sight."""
    window = sample_window(size)
    box = _animal_box(window)
    assert _in_sight(box, window)
    before = window.canvas.size()
    window.fits.fit_shown.emit()   # what a fit shown does
    qtbot.waitUntil(lambda: window.fits.viewer is not None, timeout=30_000)
    qtbot.wait(200)   # the docks' layout settles
    after = window.canvas.size()
    assert not window.docks["3D view"].isHidden()
    assert after.width() > 0.95 * before.width() and after.height() > 0.95 * before.height()
    assert _in_sight(box, window)
    window.docks["3D view"].raise_()   # one click on its tab shows it
    qtbot.waitUntil(lambda: _in_sight(window.fits.viewer, window), timeout=10_000)
    assert window.canvas.size() == after


def test_the_project_dock_shows_a_clips_status_whole(sample_window):
    """A long status (altitude missing, animals found, frames measured, fitted) fits its
    column; the clip's name gives way instead, and nothing scrolls sideways."""
    window = sample_window(SIZES[0])
    panel = window.project_panel
    panel.set_statuses([ClipStatus(has_altitude=False, animals_found=2, animals_usable=2,
                                   animals_measured=2, frames_measured=12,
                                   animals_fitted=2)])
    item, tree = panel.tree.topLevelItem(0), panel.tree
    assert item.text(1) == "no altitude · 2 found · 12 measured · 2 fitted"
    text_px = tree.fontMetrics().horizontalAdvance(item.text(1))
    assert text_px <= tree.header().sectionSize(1)
    assert tree.header().sectionSize(0) > 0
    assert not tree.horizontalScrollBar().isVisible()


def test_the_frames_dock_fits_its_width(qtbot, sample_window):
    """The scan's best frames list without a sideways scroll bar at the default dock width:
    rank, frame and as many scores as fit, left to right; a wider dock shows more of them,
    and each row's tooltip gives every score."""
    window = sample_window(SIZES[0])
    picker = window.picker
    window.actions_by_name["scan_clip"].trigger()
    qtbot.waitUntil(lambda: picker.table.rowCount() > 0
                    and not picker.table.item(0, 2).icon().isNull(), timeout=120_000)
    window.docks["Frames"].raise_()
    table = picker.table
    qtbot.wait(200)
    shown = [c for c in range(table.columnCount()) if not table.isColumnHidden(c)]
    assert not table.horizontalScrollBar().isVisible()
    assert shown == list(range(1, 1 + len(shown))) and len(shown) >= 3  # rank, frame, quality
    assert sum(table.columnWidth(c) for c in shown) <= table.viewport().width()
    assert "contrast %: " in table.item(0, 1).toolTip()
    window.resizeDocks([window.docks["Frames"]], [WIDE_DOCK_PX], Qt.Orientation.Horizontal)
    qtbot.waitUntil(lambda: sum(not table.isColumnHidden(c)
                                for c in range(table.columnCount())) > len(shown),
                    timeout=5_000)
    assert not table.horizontalScrollBar().isVisible()
