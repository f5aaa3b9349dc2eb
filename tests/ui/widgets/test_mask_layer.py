"""MaskLayer: the outline of the shown frame's mask, and brush and eraser strokes made with
real mouse events on a FrameCanvas."""

import numpy as np
import pytest
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QPainterPath
from PySide6.QtWidgets import QGraphicsPathItem

from dolphinfit.core.project.mask_store import outlines
from dolphinfit.ui.widgets.canvas import FrameCanvas
from dolphinfit.ui.widgets.mask_layer import MaskLayer

WIDTH, HEIGHT = 200, 150
VIEW_SIZE = (440, 330)  # the frame fits at 2 screen px per image px
LEFT = Qt.MouseButton.LeftButton
RADIUS_PX = 4.0
START, END = np.array([40.0, 75.0]), np.array([160.0, 75.0])


@pytest.fixture
def canvas(shown_canvas) -> FrameCanvas:
    return shown_canvas(np.full((HEIGHT, WIDTH, 3), (20, 90, 120), np.uint8), VIEW_SIZE)


@pytest.fixture
def layer(canvas) -> tuple[MaskLayer, list]:
    """A layer editing an empty mask of frame 3 with the brush; the edits it emits."""
    layer = MaskLayer(canvas)
    edits = []
    layer.mask_edited.connect(lambda frame_idx, mask: edits.append((frame_idx, mask)))
    layer.show_outlines(3, [])
    layer.begin_edit(3, np.zeros((HEIGHT, WIDTH), bool))
    layer.set_brush_radius_px(RADIUS_PX)
    layer.set_tool("brush")
    return layer, edits


def viewport_point(canvas: FrameCanvas, uv: np.ndarray) -> QPoint:
    return canvas.viewportTransform().map(QPointF(*uv)).toPoint()


def outline_path(canvas: FrameCanvas) -> QPainterPath:
    """The path of the mask layer's outline item."""
    [item] = [i for i in canvas.scene().items() if isinstance(i, QGraphicsPathItem)]
    return item.path()


def stroke(qtbot, canvas: FrameCanvas, start: np.ndarray, end: np.ndarray,
           steps: int = 6) -> None:
    """Press at ``start``, drag in ``steps`` moves to ``end``, release."""
    viewport = canvas.viewport()
    qtbot.mousePress(viewport, LEFT, pos=viewport_point(canvas, start))
    for fraction in np.linspace(0, 1, steps + 1)[1:]:
        qtbot.mouseMove(viewport, viewport_point(canvas, start + fraction * (end - start)))
    qtbot.mouseRelease(viewport, LEFT, pos=viewport_point(canvas, end))


def test_a_brush_stroke_paints_its_width_along_the_path(qtbot, canvas, layer):
    layer, edits = layer
    clicks = []
    canvas.image_clicked.connect(lambda *args: clicks.append(args))
    stroke(qtbot, canvas, START, END)
    assert len(edits) == 1 and edits[0][0] == 3
    mask = edits[0][1]
    columns = range(int(START[0]), int(END[0]) + 1)
    widths = mask[:, columns].sum(axis=0)
    assert (abs(widths - 2 * RADIUS_PX) <= 1).all()
    v, u = np.nonzero(mask)
    along = np.clip(u, *[START[0], END[0]])
    assert (np.hypot(u - along, v - START[1]) <= RADIUS_PX + 1).all()  # nothing off the path
    assert not outline_path(canvas).isEmpty()  # the outline followed the stroke
    assert clicks == []  # the canvas did not get the click


def test_the_eraser_removes_the_stroke(qtbot, canvas, layer):
    layer, edits = layer
    stroke(qtbot, canvas, START, END)
    layer.set_tool("eraser")
    layer.set_brush_radius_px(RADIUS_PX + 2)
    stroke(qtbot, canvas, END, START, steps=3)
    assert len(edits) == 2
    assert edits[0][1].any() and not edits[1][1].any()
    assert outline_path(canvas).isEmpty()


def test_without_a_tool_the_canvas_gets_the_clicks(qtbot, canvas, layer):
    layer, edits = layer
    layer.set_tool(None)
    clicks = []
    canvas.image_clicked.connect(lambda *args: clicks.append(args))
    stroke(qtbot, canvas, START, END)
    assert edits == [] and len(clicks) == 1


def test_space_drag_still_pans(qtbot, canvas, layer):
    layer, edits = layer
    before = canvas.viewportTransform().map(QPointF(0, 0))
    qtbot.keyPress(canvas, Qt.Key.Key_Space)
    stroke(qtbot, canvas, START, END)
    qtbot.keyRelease(canvas, Qt.Key.Key_Space)
    moved = canvas.viewportTransform().map(QPointF(0, 0)) - before
    assert moved.x() > 100 and edits == []


def test_outlines_show_and_another_frame_ends_the_edit(qtbot, canvas, layer):
    layer, edits = layer
    mask = np.zeros((HEIGHT, WIDTH), bool)
    mask[20:40, 50:90] = True
    layer.show_outlines(3, outlines(mask))
    rect = outline_path(canvas).boundingRect()
    assert (rect.left(), rect.top(), rect.right(), rect.bottom()) == (50, 20, 89, 39)
    layer.set_opacity(0.5)
    layer.set_fill(False)
    layer.show_outlines(4, [])
    stroke(qtbot, canvas, START, END)  # no mask of frame 4 to edit yet
    assert edits == [] and outline_path(canvas).isEmpty()
    with pytest.raises(ValueError):
        layer.set_tool("pencil")
