"""FrameCanvas: image pixel coordinates, zoom about the cursor, panning, zoom kept across frames."""

import numpy as np
import pytest
from PySide6.QtCore import QPoint, QPointF, QRectF, Qt
from PySide6.QtGui import QWheelEvent
from PySide6.QtWidgets import QApplication, QGraphicsItem, QGraphicsRectItem

from dolphinfit.ui.widgets.canvas import MAX_SCALE, MIN_ZOOM_OF_FIT, ZOOM_STEP, FrameCanvas

WIDTH, HEIGHT = 640, 480
VIEW_W, VIEW_H = 800, 600
RED_PIXEL = (100, 50)  # (u, v): the only non-black pixel


def synthetic_frame(width: int = WIDTH, height: int = HEIGHT) -> np.ndarray:
    rgb = np.zeros((height, width, 3), dtype=np.uint8)
    rgb[RED_PIXEL[1], RED_PIXEL[0]] = (255, 0, 0)
    return rgb


@pytest.fixture
def canvas(qtbot):
    view = FrameCanvas()
    qtbot.addWidget(view)
    view.resize(VIEW_W, VIEW_H)
    view.show()
    qtbot.waitExposed(view)
    view.set_frame(synthetic_frame())
    return view


def scene_at(canvas: FrameCanvas, pos: QPoint | QPointF) -> np.ndarray:
    point = canvas.viewportTransform().inverted()[0].map(QPointF(pos))
    return np.array([point.x(), point.y()])


def viewport_at(canvas: FrameCanvas, u: float, v: float) -> QPoint:
    return canvas.viewportTransform().map(QPointF(u, v)).toPoint()


def wheel(canvas: FrameCanvas, pos: QPoint, notches: int) -> None:
    event = QWheelEvent(QPointF(pos), QPointF(canvas.viewport().mapToGlobal(pos)), QPoint(),
                        QPoint(0, 120 * notches), Qt.MouseButton.NoButton,
                        Qt.KeyboardModifier.NoModifier, Qt.ScrollPhase.NoScrollPhase, False)
    QApplication.sendEvent(canvas.viewport(), event)


def test_the_first_frame_fits_and_is_centred(canvas):
    viewport = canvas.viewport().rect()
    fit = min(viewport.width() / WIDTH, viewport.height() / HEIGHT)
    assert canvas.view_scale() == pytest.approx(fit)
    centre = scene_at(canvas, QRectF(viewport).center())
    np.testing.assert_allclose(centre, [WIDTH / 2 - 0.5, HEIGHT / 2 - 0.5], atol=1 / fit)


def test_wheel_zooms_about_the_cursor(canvas):
    pos = QPoint(300, 200)
    before, scale = scene_at(canvas, pos), canvas.view_scale()
    wheel(canvas, pos, 2)
    assert canvas.view_scale() == pytest.approx(scale * ZOOM_STEP**2)
    np.testing.assert_allclose(scene_at(canvas, pos), before, atol=1.0)
    pos = QPoint(600, 450)
    before = scene_at(canvas, pos)
    wheel(canvas, pos, -1)
    np.testing.assert_allclose(scene_at(canvas, pos), before, atol=1.0)


def test_zoom_is_clamped(canvas):
    fit = canvas.view_scale()
    wheel(canvas, QPoint(400, 300), -40)
    assert canvas.view_scale() == pytest.approx(MIN_ZOOM_OF_FIT * fit)
    wheel(canvas, QPoint(400, 300), 80)
    assert canvas.view_scale() == pytest.approx(MAX_SCALE)


def test_fit_to_window_after_zooming(canvas):
    fit = canvas.view_scale()
    wheel(canvas, QPoint(100, 100), 5)
    canvas.fit_to_window()
    assert canvas.view_scale() == pytest.approx(fit)


def test_zoom_and_pan_are_kept_across_frames_of_the_same_size(canvas):
    wheel(canvas, QPoint(250, 350), 4)
    transform = canvas.viewportTransform()
    canvas.set_frame(synthetic_frame()[::-1].copy())
    assert canvas.viewportTransform() == transform
    canvas.set_frame(synthetic_frame(320, 240))  # a new size fits again
    assert canvas.view_scale() == pytest.approx(min(VIEW_W / 320, VIEW_H / 240))


def test_middle_drag_pans(qtbot, canvas):
    wheel(canvas, QPoint(400, 300), 3)
    scale = canvas.view_scale()
    grabbed = scene_at(canvas, QPoint(400, 300))
    viewport = canvas.viewport()
    qtbot.mousePress(viewport, Qt.MouseButton.MiddleButton, pos=QPoint(400, 300))
    qtbot.mouseMove(viewport, QPoint(430, 320))
    qtbot.mouseMove(viewport, QPoint(470, 340))
    qtbot.mouseRelease(viewport, Qt.MouseButton.MiddleButton, pos=QPoint(470, 340))
    assert canvas.view_scale() == scale
    np.testing.assert_allclose(scene_at(canvas, QPoint(470, 340)), grabbed, atol=1 / scale)


def test_space_left_drag_pans_without_clicking(qtbot, canvas):
    clicks, taps = [], []
    canvas.image_clicked.connect(lambda *args: clicks.append(args))
    canvas.space_tapped.connect(lambda: taps.append(True))
    grabbed = scene_at(canvas, QPoint(400, 300))
    viewport = canvas.viewport()
    qtbot.keyPress(canvas, Qt.Key.Key_Space)
    qtbot.mousePress(viewport, Qt.MouseButton.LeftButton, pos=QPoint(400, 300))
    qtbot.mouseMove(viewport, QPoint(350, 280))
    qtbot.mouseRelease(viewport, Qt.MouseButton.LeftButton, pos=QPoint(350, 280))
    qtbot.keyRelease(canvas, Qt.Key.Key_Space)
    np.testing.assert_allclose(scene_at(canvas, QPoint(350, 280)), grabbed,
                               atol=1 / canvas.view_scale())
    assert clicks == [] and taps == []
    qtbot.keyClick(canvas, Qt.Key.Key_Space)  # a tap without dragging
    assert taps == [True]


def test_a_click_gives_image_pixel_coordinates_with_centres_at_integers(qtbot, canvas):
    u, v = RED_PIXEL
    canvas.zoom_to(QRectF(u - 5, v - 5, 10, 10))
    assert canvas.view_scale() > 40
    pos = viewport_at(canvas, u, v)
    # The pixel's centre is drawn in its own colour: the pixmap sits at offset (-0.5, -0.5).
    rendered = canvas.viewport().grab().toImage().pixelColor(pos)
    assert rendered.red() > 240 and rendered.green() < 15
    with qtbot.waitSignal(canvas.image_clicked, timeout=1000) as blocker:
        qtbot.mouseClick(canvas.viewport(), Qt.MouseButton.LeftButton,
                         Qt.KeyboardModifier.ShiftModifier, pos)
    clicked_u, clicked_v, modifiers = blocker.args
    assert abs(clicked_u - u) < 0.5 and abs(clicked_v - v) < 0.5
    assert modifiers == Qt.KeyboardModifier.ShiftModifier


def test_no_click_on_an_item_that_takes_the_press_nor_off_the_image(qtbot, canvas):
    handle = QGraphicsRectItem(200, 200, 40, 40)
    handle.setFlag(QGraphicsItem.GraphicsItemFlag.ItemIsMovable)
    handle.setZValue(1)
    canvas.scene().addItem(handle)
    with qtbot.assertNotEmitted(canvas.image_clicked):
        qtbot.mouseClick(canvas.viewport(), Qt.MouseButton.LeftButton,
                         pos=viewport_at(canvas, 220, 220))
        qtbot.mouseClick(canvas.viewport(), Qt.MouseButton.LeftButton,
                         pos=viewport_at(canvas, -20, 100))
    with qtbot.waitSignal(canvas.image_clicked, timeout=1000):
        qtbot.mouseClick(canvas.viewport(), Qt.MouseButton.LeftButton,
                         pos=viewport_at(canvas, 300, 100))


def test_cursor_moves_are_reported_in_image_pixels(qtbot, canvas):
    pos = viewport_at(canvas, 123, 45)
    with qtbot.waitSignal(canvas.cursor_moved, timeout=1000) as blocker:
        qtbot.mouseMove(canvas.viewport(), pos)
    np.testing.assert_allclose(blocker.args, [123, 45], atol=1 / canvas.view_scale())
