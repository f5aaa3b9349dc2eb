"""The mask layer of the frame view: the shown frame's mask outline, and a brush and an eraser
that correct that frame's mask.

Outlines come precomputed (core.project.mask_store.outlines, in a job). While a tool is on,
a left drag on the canvas paints (brush) or clears (eraser) every pixel within the brush
radius of the drag's path on a copy of the mask given by ``begin_edit``; the outline follows
live, and the release emits ``mask_edited`` once per stroke. Space + drag still pans and the
wheel still zooms; clicks then do not reach the canvas (no measuring clicks while painting).
"""

from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np
from PySide6.QtCore import QEvent, QObject, QPointF, QRectF, Qt, Signal
from PySide6.QtGui import QBrush, QColor, QKeyEvent, QMouseEvent, QPainterPath, QPolygonF
from PySide6.QtWidgets import QGraphicsEllipseItem, QGraphicsPathItem

from dolphinfit.core.project.mask_store import outlines, paint_segment
from dolphinfit.ui.widgets.canvas import FrameCanvas
from dolphinfit.ui.widgets.overlay_items import cosmetic_pen

MASK_Z = 5  # above the frame (z = 0), below the measuring overlay (z = 10)
CURSOR_Z = 20
OUTLINE_COLOUR = QColor(60, 255, 120)
FILL_COLOUR = QColor(60, 255, 120, 60)
CURSOR_COLOUR = QColor(255, 255, 255, 200)
TOOLS = ("brush", "eraser")
DEFAULT_BRUSH_RADIUS_PX = 6.0  # image px
PRESS_EVENTS = (QEvent.Type.MouseButtonPress, QEvent.Type.MouseButtonDblClick)

Window = tuple[int, int, int, int]  # row0, row1, col0, col1 (ends excluded)


@dataclass
class _Edit:
    """The mask being corrected and a window (image px) holding all of its pixels."""

    frame_idx: int
    mask: np.ndarray
    window: Window | None


def _union(window: Window | None, rows: slice, cols: slice) -> Window:
    if window is None:
        return rows.start, rows.stop, cols.start, cols.stop
    return (min(window[0], rows.start), max(window[1], rows.stop),
            min(window[2], cols.start), max(window[3], cols.stop))


def _path(polygons: Sequence[np.ndarray]) -> QPainterPath:
    path = QPainterPath()
    for polygon in polygons:
        path.addPolygon(QPolygonF([QPointF(u, v) for u, v in polygon]))
        path.closeSubpath()
    return path


class MaskLayer(QObject):
    """Draws one frame's mask outline on ``canvas`` and edits that frame's mask."""

    mask_edited = Signal(int, object)  # frame index, the corrected (H, W) bool mask

    def __init__(self, canvas: FrameCanvas) -> None:
        super().__init__(canvas)
        self._canvas = canvas
        self._outline = QGraphicsPathItem()
        self._outline.setPen(cosmetic_pen(OUTLINE_COLOUR))
        self._outline.setBrush(FILL_COLOUR)
        self._outline.setZValue(MASK_Z)
        self._cursor = QGraphicsEllipseItem()
        self._cursor.setPen(cosmetic_pen(CURSOR_COLOUR, dashed=True))
        self._cursor.setZValue(CURSOR_Z)
        self._cursor.hide()
        for item in (self._outline, self._cursor):
            canvas.scene().addItem(item)
        self._tool: str | None = None
        self._radius_px = DEFAULT_BRUSH_RADIUS_PX
        self._frame_idx: int | None = None  # the frame whose outline is shown
        self._edit: _Edit | None = None
        self._last_uv: tuple[float, float] | None = None  # the stroke in progress
        self._space_held = False  # the canvas's pan modifier
        canvas.installEventFilter(self)
        canvas.viewport().installEventFilter(self)

    # --- display -----------------------------------------------------------------------------

    def set_visible(self, visible: bool) -> None:
        self._outline.setVisible(visible)

    def set_opacity(self, opacity: float) -> None:
        """0 (invisible) to 1."""
        self._outline.setOpacity(opacity)

    def set_fill(self, fill: bool) -> None:
        """Fill the mask semi-transparently, or draw its outline only."""
        self._outline.setBrush(FILL_COLOUR if fill else QBrush(Qt.BrushStyle.NoBrush))

    def outline_path(self) -> QPainterPath:
        """The outline drawn now (image pixels)."""
        return self._outline.path()

    def show_outlines(self, frame_idx: int, polygons: Sequence[np.ndarray]) -> None:
        """Draw frame ``frame_idx``'s outlines ((N, 2) u, v polygons, image px). An edit of
        another frame ends (its strokes were already emitted)."""
        if self._edit is not None and self._edit.frame_idx != frame_idx:
            self._end_stroke()
            self._edit = None
        self._frame_idx = frame_idx
        self._outline.setPath(_path(polygons))

    def clear(self) -> None:
        """No outline and nothing to edit (no masks, or another clip)."""
        self._end_stroke()
        self._edit = None
        self._frame_idx = None
        self._outline.setPath(QPainterPath())

    # --- editing -----------------------------------------------------------------------------

    @property
    def tool(self) -> str | None:
        return self._tool

    def set_tool(self, tool: str | None) -> None:
        """None (the canvas gets its clicks), "brush" or "eraser"; ends a stroke in progress."""
        if tool is not None and tool not in TOOLS:
            raise ValueError(f"tool must be None or one of {TOOLS}, got {tool!r}")
        self._end_stroke()
        self._tool = tool
        if tool is None:
            self._cursor.hide()

    def set_brush_radius_px(self, radius_px: float) -> None:
        """The brush's and the eraser's radius, image px (> 0)."""
        if not radius_px > 0:
            raise ValueError(f"brush radius must be > 0 image px, got {radius_px!r}")
        self._radius_px = float(radius_px)
        self._place_cursor(self._cursor.rect().center())

    @property
    def editing_frame(self) -> int | None:
        """The frame whose mask strokes correct (None until a frame's mask is handed over)."""
        return None if self._edit is None else self._edit.frame_idx

    def begin_edit(self, frame_idx: int, mask: np.ndarray) -> None:
        """Strokes from now on correct a copy of ``mask`` ((H, W), non-zero = dolphin), frame
        ``frame_idx``'s mask; each stroke's result is emitted and edited further."""
        self._end_stroke()
        mask = np.asarray(mask) != 0
        col0, row0, width, height = cv2.boundingRect(mask.astype(np.uint8))
        window = (row0, row0 + height, col0, col0 + width) if width else None
        self._edit = _Edit(frame_idx, mask, window)

    # --- events ------------------------------------------------------------------------------

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:  # noqa: N802 (Qt's name)
        if watched is self._canvas:
            self._track_space(event)
            return False
        if self._tool is None:
            return False
        kind = event.type()
        if kind in PRESS_EVENTS and event.button() == Qt.MouseButton.LeftButton \
                and not self._space_held:
            uv = self._uv(event)
            self._paint(uv, uv)  # a stroke starts with one disc
            return True
        if kind == QEvent.Type.MouseMove:
            uv = self._uv(event)
            self._place_cursor(QPointF(*uv))
            self._cursor.show()
            if self._last_uv is not None:
                self._paint(self._last_uv, uv)
            return False  # the canvas still reports the cursor position
        if kind == QEvent.Type.MouseButtonRelease and self._last_uv is not None \
                and event.button() == Qt.MouseButton.LeftButton:
            self._end_stroke()
            return True
        if kind == QEvent.Type.Leave:
            self._cursor.hide()
        return False

    def _track_space(self, event: QEvent) -> None:
        """Follow Space as FrameCanvas does: held, it makes a left drag pan."""
        kind = event.type()
        if kind in (QEvent.Type.KeyPress, QEvent.Type.KeyRelease):
            key_event: QKeyEvent = event
            if key_event.key() == Qt.Key.Key_Space and not key_event.isAutoRepeat():
                self._space_held = kind == QEvent.Type.KeyPress
        elif kind == QEvent.Type.FocusOut:
            self._space_held = False

    def _uv(self, event: QMouseEvent) -> tuple[float, float]:
        point = self._canvas.viewportTransform().inverted()[0].map(event.position())
        return point.x(), point.y()

    def _place_cursor(self, centre: QPointF) -> None:
        r = self._radius_px
        self._cursor.setRect(QRectF(centre.x() - r, centre.y() - r, 2 * r, 2 * r))

    def _paint(self, start_uv: tuple[float, float], end_uv: tuple[float, float]) -> None:
        """One step of the stroke (the first starts it), and the outline redrawn live."""
        self._last_uv = end_uv
        edit = self._edit
        if edit is None:
            return
        rows, cols = paint_segment(edit.mask, start_uv, end_uv, self._radius_px,
                                   self._tool == "brush")
        if rows.start < rows.stop and cols.start < cols.stop:
            edit.window = _union(edit.window, rows, cols)
        if edit.window is not None:
            row0, row1, col0, col1 = edit.window
            shown = outlines(edit.mask[row0:row1, col0:col1])
            self._outline.setPath(_path([p + (col0, row0) for p in shown]))

    def _end_stroke(self) -> None:
        """Emit the stroke in progress, if any."""
        if self._last_uv is None:
            return
        self._last_uv = None
        if self._edit is not None:
            self.mask_edited.emit(self._edit.frame_idx, self._edit.mask.copy())
