"""The measuring overlay driven by real mouse and key events on a FrameCanvas, on the
ellipse scene of ellipse_scene.py (every length, edge and width has an analytic value)."""

import numpy as np
import pytest
from PySide6.QtCore import QPoint, QPointF, QRectF, Qt
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QGraphicsEllipseItem

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation import pixel_measurements, place_stations
from dolphinfit.core.measure.stations import NUM_STATIONS
from dolphinfit.core.project.model import Animal, ClipEntry, Measurement, Project
from dolphinfit.ui.widgets.canvas import FrameCanvas
from dolphinfit.ui.widgets.measure_overlay import MeasureOverlay, handle_order
from dolphinfit.ui.widgets.overlay_items import HandleItem, LabelItem
from dolphinfit.ui.state.project_model import ProjectModel

from ..ellipse_scene import (
    AXIS_ENDS, CENTRE, HEIGHT, LEFT, MIDLINE, SEMI_AXES, VIEW_SIZE, WIDTH, analytic_widths, chord,
    dolphin_frame, dolphin_mask,
)

def measured() -> Measurement:
    """Midline along the major axis, every edge on the outline."""
    stations = place_stations(MIDLINE)
    offsets = [chord(p, n) for p, n in zip(stations.points_px, stations.normals)]
    return Measurement(frame_idx=0, midline_px=MIDLINE, offsets_px=offsets)


def widths_of(model: ProjectModel) -> np.ndarray:
    return pixel_measurements(model.current_measurement().to_annotation()).widths_px


@pytest.fixture
def canvas(shown_canvas) -> FrameCanvas:
    view = shown_canvas(dolphin_frame(), VIEW_SIZE)
    assert view.view_scale() == pytest.approx(1.5)
    return view


@pytest.fixture
def overlay_for(canvas):
    """Builds a one-clip project around a measurement of frame 0 and its overlay."""
    camera = CameraPreset(name="test", description="test camera", focal_mm=10.0,
                          sensor_width_mm=13.2, image_width_px=WIDTH, image_height_px=HEIGHT,
                          source="test", approximate=False)

    models = []

    def build(measurement: Measurement) -> tuple[MeasureOverlay, ProjectModel]:
        animal = Animal("dolphin 1", measurements=(measurement,))
        clip = ClipEntry(media_path="clip.mp4", kind="video", camera=camera, animals=(animal,))
        models.append(ProjectModel(Project(clips=(clip,))))
        overlay = MeasureOverlay(canvas, models[-1])
        overlay.set_frame(0)
        return overlay, models[-1]

    yield build
    for model in models:  # while alive: a stack cleared on deletion signals a deleted model
        model.undo_stack.clear()


def viewport_point(canvas: FrameCanvas, uv: np.ndarray) -> QPoint:
    return canvas.mapFromScene(QPointF(*uv))


def image_point(canvas: FrameCanvas, pos: QPoint) -> np.ndarray:
    """Where a press at viewport ``pos`` lands on the image (clicks snap to screen pixels)."""
    scene = canvas.mapToScene(pos)
    return np.array([scene.x(), scene.y()])


def click(qtbot, canvas: FrameCanvas, uv: np.ndarray,
          button: Qt.MouseButton = LEFT,
          modifier: Qt.KeyboardModifier = Qt.KeyboardModifier.NoModifier) -> np.ndarray:
    """Click the image at ``uv``; returns the image point the click implies."""
    pos = viewport_point(canvas, uv)
    qtbot.mouseClick(canvas.viewport(), button, modifier, pos)
    return image_point(canvas, pos)


def drag(qtbot, canvas: FrameCanvas, uv: np.ndarray, by: QPoint) -> np.ndarray:
    """Press at ``uv``, move by ``by`` screen px in two steps, release; the image shift."""
    start = viewport_point(canvas, uv)
    assert isinstance(canvas.itemAt(start), HandleItem)
    qtbot.mousePress(canvas.viewport(), LEFT, pos=start)
    qtbot.mouseMove(canvas.viewport(), start + by / 2)
    qtbot.mouseMove(canvas.viewport(), start + by)
    qtbot.mouseRelease(canvas.viewport(), LEFT, pos=start + by)
    return image_point(canvas, start + by) - image_point(canvas, start)


def visible_items(canvas: FrameCanvas, kind: type) -> list:
    return [item for item in canvas.scene().items() if isinstance(item, kind) and item.isVisible()]


def test_length_then_widths_by_clicks(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(Measurement(frame_idx=0))
    rostrum = click(qtbot, canvas, AXIS_ENDS[0])
    notch = click(qtbot, canvas, AXIS_ENDS[1])
    middle = click(qtbot, canvas, CENTRE, modifier=Qt.KeyboardModifier.ControlModifier)
    m = model.current_measurement()
    np.testing.assert_allclose(m.midline_px, [rostrum, middle, notch], atol=1e-9)
    stations = place_stations(m.midline_px)
    assert stations.length_px == pytest.approx(2 * SEMI_AXES[0], abs=1.0)
    assert overlay.selected_point == 1

    overlay.set_mode("widths")
    visited, implied = [], np.full((NUM_STATIONS, 2), np.nan)
    for _ in range(2 * NUM_STATIONS):
        station, side = overlay.selected_edge
        visited.append((station, side))
        point, normal = stations.points_px[station], stations.normals[station]
        hit = click(qtbot, canvas, point + chord(point, normal)[side] * normal)
        implied[station, side] = (hit - point) @ normal
    assert visited == handle_order(m)
    widths = widths_of(model)
    np.testing.assert_allclose(widths, implied[:, 0] - implied[:, 1], atol=1e-9)
    assert np.abs(widths - analytic_widths(m.midline_px)).max() < 1.0
    assert len(visible_items(canvas, HandleItem)) == 2 * NUM_STATIONS
    assert model.undo_stack.count() == 3 + 2 * NUM_STATIONS


def test_midline_points_drag_and_delete(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(Measurement(frame_idx=0))
    click(qtbot, canvas, AXIS_ENDS[0])
    click(qtbot, canvas, AXIS_ENDS[0])  # lands on the point's handle: moves nothing
    assert len(model.current_measurement().midline_px) == 1
    for uv in (CENTRE, AXIS_ENDS[1]):
        click(qtbot, canvas, uv)
    before = model.current_measurement().midline_px.copy()
    count = model.undo_stack.count()

    shift = drag(qtbot, canvas, before[1], QPoint(9, -6))
    np.testing.assert_allclose(model.current_measurement().midline_px[1], before[1] + shift)
    assert model.undo_stack.count() == count + 1  # one undo step for the whole drag
    model.undo_stack.undo()
    np.testing.assert_allclose(model.current_measurement().midline_px, before)

    click(qtbot, canvas, before[1], button=Qt.MouseButton.RightButton)
    np.testing.assert_allclose(model.current_measurement().midline_px, before[[0, 2]])
    assert overlay.selected_point == 0
    qtbot.keyClick(canvas, Qt.Key.Key_Delete)
    np.testing.assert_allclose(model.current_measurement().midline_px, before[[2]])
    assert overlay.selected_point is None
    assert len(visible_items(canvas, HandleItem)) == 1


def test_refused_edit_is_a_status_message(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(Measurement(frame_idx=0, midline_px=MIDLINE[:2]))
    with qtbot.waitSignal(overlay.status_message, timeout=1000) as signal:
        canvas.image_clicked.emit(*MIDLINE[1], Qt.KeyboardModifier.NoModifier)
    assert "refused" in signal.args[0]
    np.testing.assert_array_equal(model.current_measurement().midline_px, MIDLINE[:2])
    assert model.undo_stack.count() == 0


def test_drag_width_handle_is_one_undo_step(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(measured())
    overlay.set_mode("widths")
    before = model.current_measurement().offsets_px.copy()
    stations = place_stations(MIDLINE)
    station = 9
    handle = stations.points_px[station] + before[station, 0] * stations.normals[station]
    with qtbot.waitSignal(overlay.selection_changed, timeout=1000) as signal:
        shift = drag(qtbot, canvas, handle, QPoint(7, -15))
    assert signal.args == [station, 0]
    after = model.current_measurement().offsets_px
    assert after[station, 0] == pytest.approx(before[station, 0] + shift @ stations.normals[9])
    np.testing.assert_array_equal(np.delete(after, station, axis=0),
                                  np.delete(before, station, axis=0))
    assert model.undo_stack.count() == 1
    model.undo_stack.undo()
    np.testing.assert_array_equal(model.current_measurement().offsets_px, before)


def test_multi_level_undo_redo_redraws(qtbot, canvas, overlay_for):
    _, model = overlay_for(Measurement(frame_idx=0))
    clicks = [click(qtbot, canvas, uv) for uv in MIDLINE]
    model.undo_stack.undo()
    model.undo_stack.undo()
    np.testing.assert_allclose(model.current_measurement().midline_px, clicks[:1])
    assert len(visible_items(canvas, HandleItem)) == 1
    model.undo_stack.redo()
    np.testing.assert_allclose(model.current_measurement().midline_px, clicks[:2])
    drawn = sorted((h.pos().x(), h.pos().y()) for h in visible_items(canvas, HandleItem))
    np.testing.assert_allclose(drawn, sorted(map(tuple, clicks[:2])))


def test_tab_order_and_arrow_nudges(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(measured())
    overlay.set_mode("widths")
    canvas.activateWindow()
    canvas.setFocus()
    qtbot.waitUntil(canvas.hasFocus, timeout=2000)  # window shortcuts see the focused widget
    triggered = []
    for key in (Qt.Key.Key_Left, Qt.Key.Key_Up):
        action = QAction(canvas)
        action.setShortcut(QKeySequence(key))
        action.setShortcutContext(Qt.ShortcutContext.ApplicationShortcut)
        action.triggered.connect(lambda _=False, key=key: triggered.append(key))
        canvas.addAction(action)
    assert overlay.selected_edge == (0, 0)
    qtbot.keyClick(canvas, Qt.Key.Key_Tab)
    assert overlay.selected_edge == (0, 1)
    qtbot.keyClick(canvas, Qt.Key.Key_Tab)
    assert overlay.selected_edge == (1, 0)
    qtbot.keyClick(canvas, Qt.Key.Key_Backtab, Qt.KeyboardModifier.ShiftModifier)
    assert overlay.selected_edge == (0, 1)

    start = model.current_measurement().offsets_px.copy()

    def moved() -> np.ndarray:
        return model.current_measurement().offsets_px - start

    qtbot.keyClick(canvas, Qt.Key.Key_Up)  # side B: outward is towards negative offsets
    assert moved()[0, 1] == pytest.approx(-1.0)
    qtbot.keyClick(canvas, Qt.Key.Key_Backtab, Qt.KeyboardModifier.ShiftModifier)
    qtbot.keyClick(canvas, Qt.Key.Key_Up)
    assert moved()[0, 0] == pytest.approx(1.0)
    qtbot.keyClick(canvas, Qt.Key.Key_Up, Qt.KeyboardModifier.AltModifier)
    assert moved()[0, 0] == pytest.approx(1.1)
    qtbot.keyClick(canvas, Qt.Key.Key_Down, Qt.KeyboardModifier.ShiftModifier)
    assert moved()[0, 0] == pytest.approx(-3.9)
    assert widths_of(model)[0] == pytest.approx(analytic_widths(MIDLINE)[0] - 3.9 + 1.0)
    qtbot.keyClick(canvas, Qt.Key.Key_Left)
    assert triggered == [Qt.Key.Key_Left]  # Left stays the window's; Up was the overlay's
    assert overlay.selected_edge == (0, 0)
    model.undo_stack.undo()  # the nudges of side A merged into one step
    np.testing.assert_allclose(moved()[0], [0.0, -1.0])
    overlay.set_mode("length")
    qtbot.keyClick(canvas, Qt.Key.Key_Up)
    assert triggered == [Qt.Key.Key_Left, Qt.Key.Key_Up]  # not the overlay's in length mode


def test_remove_edges_by_right_click_and_delete(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(measured())
    overlay.set_mode("widths")
    stations = place_stations(MIDLINE)
    offsets = model.current_measurement().offsets_px
    handle = stations.points_px[6] + offsets[6, 1] * stations.normals[6]
    click(qtbot, canvas, handle, button=Qt.MouseButton.RightButton)
    assert np.isnan(model.current_measurement().offsets_px[6, 1])
    assert overlay.selected_edge == (0, 0)
    qtbot.keyClick(canvas, Qt.Key.Key_Delete)
    assert np.isnan(model.current_measurement().offsets_px[0, 0])
    assert len(visible_items(canvas, HandleItem)) == 2 * NUM_STATIONS - 2
    markers = visible_items(canvas, QGraphicsEllipseItem)  # the selected, unplaced handle
    assert [(mk.pos().x(), mk.pos().y()) for mk in markers] == [tuple(stations.points_px[0])]
    qtbot.keyClick(canvas, Qt.Key.Key_Delete)  # nothing left to remove: no empty undo step
    assert model.undo_stack.count() == 2


def test_nudge_never_crosses_the_midline(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(measured())
    overlay.set_mode("widths")
    for _ in range(6):  # 30 px inward: the edge is 26 px from the midline
        qtbot.keyClick(canvas, Qt.Key.Key_Down, Qt.KeyboardModifier.ShiftModifier)
    assert model.current_measurement().offsets_px[0, 0] == 0.0


def test_skip_station(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(measured())
    overlay.set_mode("widths")
    for _ in range(8):
        overlay.next_handle()
    assert overlay.selected_edge == (4, 0)
    overlay.skip_station()
    assert model.current_measurement().skipped[4]
    assert overlay.selected_edge == (5, 0)
    widths = widths_of(model)
    assert np.isnan(widths[4]) and np.isfinite(np.delete(widths, 4)).all()
    assert [label.text() for label in visible_items(canvas, LabelItem)].count("skip") == 1
    assert len(visible_items(canvas, HandleItem)) == 2 * NUM_STATIONS - 2
    model.undo_stack.undo()
    assert not model.current_measurement().skipped.any()


def test_mirror_side_a(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(measured())
    overlay.set_mode("widths")
    qtbot.keyClick(canvas, Qt.Key.Key_Tab)
    assert overlay.selected_edge == (0, 1)
    overlay.set_mirror_side("A")
    offsets = model.current_measurement().offsets_px
    np.testing.assert_allclose(widths_of(model), 2 * offsets[:, 0])
    assert overlay.selected_edge == (0, 0)
    qtbot.keyClick(canvas, Qt.Key.Key_Tab)
    assert overlay.selected_edge == (1, 0)
    stations = place_stations(MIDLINE)
    ghosts = [h for h in visible_items(canvas, HandleItem)
              if h.acceptedMouseButtons() == Qt.MouseButton.NoButton]
    expected = stations.points_px - offsets[:, :1] * stations.normals
    drawn = np.array([(g.pos().x(), g.pos().y()) for g in ghosts])
    assert len(drawn) == NUM_STATIONS
    for point in expected:
        assert np.linalg.norm(drawn - point, axis=1).min() < 1e-9
    assert len(visible_items(canvas, HandleItem)) == 2 * NUM_STATIONS  # A handles and ghosts


def test_reverse_direction_keeps_widths(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(measured())
    overlay.set_mode("widths")
    before = widths_of(model)
    stations = place_stations(MIDLINE)
    overlay.next_handle()
    overlay.reverse_direction()
    m = model.current_measurement()
    np.testing.assert_array_equal(m.midline_px, MIDLINE[::-1])
    np.testing.assert_allclose(widths_of(model), before[::-1], atol=1e-6)
    reversed_stations = place_stations(m.midline_px)
    np.testing.assert_allclose(reversed_stations.points_px, stations.points_px[::-1], atol=1e-6)
    assert overlay.selected_edge == (NUM_STATIONS - 1, 0)  # side B of 5 % is side A of 95 %


def test_suggest_edges_from_mask(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(Measurement(frame_idx=0, midline_px=MIDLINE))
    overlay.suggest_edges(dolphin_mask())
    assert np.abs(widths_of(model) - analytic_widths(MIDLINE)).max() < 1.0
    assert model.undo_stack.count() == 1
    model.undo_stack.undo()
    assert np.isnan(model.current_measurement().offsets_px).all()
    with pytest.raises(InputError, match="mask"):
        overlay.suggest_edges(dolphin_mask().T)


def test_edge_sources_of_suggest_drag_nudge_and_click(qtbot, canvas, overlay_for):
    """Suggested edges stay suggested until dragged or nudged; a click makes one clicked;
    undo brings each source back."""
    overlay, model = overlay_for(Measurement(frame_idx=0, midline_px=MIDLINE))
    overlay.set_mode("widths")
    overlay.suggest_edges(dolphin_mask())

    def sources() -> np.ndarray:
        return model.current_measurement().edge_sources

    assert (sources() == "suggested").all()
    stations, offsets = place_stations(MIDLINE), model.current_measurement().offsets_px
    drag(qtbot, canvas, stations.points_px[9] + offsets[9, 0] * stations.normals[9],
         QPoint(3, -12))
    assert overlay.selected_edge == (9, 0) and sources()[9, 0] == "suggested_moved"
    overlay.next_handle()
    overlay.nudge(1)
    assert sources()[9, 1] == "suggested_moved"
    overlay.next_handle()
    point, normal = stations.points_px[10], stations.normals[10]
    click(qtbot, canvas, point + (offsets[10, 0] + 15.0) * normal)
    assert model.current_measurement().offsets_px[10, 0] == pytest.approx(
        offsets[10, 0] + 15.0, abs=1.0)
    assert sources()[10, 0] == "clicked"
    assert (np.delete(sources().ravel(), [18, 19, 20]) == "suggested").all()
    for edge in ((10, 0), (9, 1), (9, 0)):
        model.undo_stack.undo()
        assert sources()[edge] == "suggested"


def test_handles_keep_their_screen_size_at_any_zoom(qtbot, canvas, overlay_for):
    overlay, _ = overlay_for(measured())
    overlay.set_mode("widths")
    handle = next(h for h in visible_items(canvas, HandleItem) if h.tag == ("edge", 9, 0))

    def on_screen() -> float:
        return handle.deviceTransform(canvas.viewportTransform()).mapRect(
            handle.boundingRect()).width()

    size = on_screen()
    canvas.zoom_to(QRectF(350, 150, 60, 30))
    assert canvas.view_scale() > 10
    assert on_screen() == pytest.approx(size)
    style = overlay.style
    overlay.set_style(type(style)(size_px=style.size_px + 10, shape="ring"))
    assert on_screen() == pytest.approx(size + 10)


def test_auto_zoom_centres_the_next_station(qtbot, canvas, overlay_for):
    overlay, _ = overlay_for(measured())
    overlay.set_mode("widths")
    overlay.auto_zoom = True
    overlay.next_handle()
    overlay.next_handle()
    stations = place_stations(MIDLINE)
    box = 0.3 * stations.length_px
    assert canvas.view_scale() == pytest.approx(min(VIEW_SIZE) / box)
    centre = canvas.mapFromScene(QPointF(*stations.points_px[1]))
    assert abs(centre.x() - VIEW_SIZE[0] / 2) <= 1 and abs(centre.y() - VIEW_SIZE[1] / 2) <= 1


def test_drawn_only_on_its_frame(qtbot, canvas, overlay_for):
    overlay, model = overlay_for(measured())
    overlay.set_frame(1)
    assert not visible_items(canvas, HandleItem)
    with qtbot.waitSignal(overlay.status_message, timeout=1000):
        click(qtbot, canvas, CENTRE)
    assert model.undo_stack.count() == 0
    overlay.set_frame(0)
    assert len(visible_items(canvas, HandleItem)) == len(MIDLINE)
