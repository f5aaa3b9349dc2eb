"""Graphics items of the measuring overlay, and the set of them that draws one measurement.

Handles, labels and markers ignore the view's transformation (ItemIgnoresTransformations):
their own coordinates are screen pixels about their scene position, so they keep their size at
any zoom. Lines live in scene (image pixel) coordinates and use cosmetic pens, whose width is
in screen pixels.
"""

from collections.abc import Hashable, Iterable
from typing import Protocol

import numpy as np
from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QColor, QPainter, QPainterPath, QPen, QPolygonF, QTransform
from PySide6.QtWidgets import (QGraphicsEllipseItem, QGraphicsItem, QGraphicsLineItem,
                               QGraphicsPathItem, QGraphicsScene, QGraphicsSceneMouseEvent,
                               QGraphicsSimpleTextItem, QStyleOptionGraphicsItem, QWidget)

from dolphinfit.core.measure.annotation import Stations, midline_spline
from dolphinfit.core.measure.stations import NUM_STATIONS, STATION_PCT
from dolphinfit.core.project.model import Measurement
from dolphinfit.ui.state.handle_style import HandleStyle

OVERLAY_Z = 10  # above the frame's pixmap (z = 0)
PERPENDICULAR_HALF_LENGTH = 0.15  # of body length: past the widest body (≈ 0.09) and flippers
CURVE_SAMPLES_PER_SPAN = 32  # polyline points drawn per midline click interval
OPEN_CENTRE = 0.35  # fraction of a cross's half-size left empty at its centre
PEN_PX = 1.5  # stroke width, screen px
SELECTED_PEN_SCALE = 1.6  # a selected handle's strokes are this much wider
SELECTED_GAP_PX = 4.0  # a selected handle's ring lies this far outside it, screen px
MARKER_RADIUS_PX = 4.0  # the selected but unplaced handle's dot on the midline
GHOST_OPACITY = 0.7  # of the style's opacity; a ghost is also a dashed ring, whatever the shape
HALO = QColor(0, 0, 0, 150)  # dark outline under each stroke, for contrast on bright water
LINE_COLOUR = QColor(255, 255, 255, 110)
SELECTED_LINE_COLOUR = QColor(255, 255, 255, 230)
SKIPPED_COLOUR = QColor(170, 170, 170, 210)
LABEL_COLOUR = QColor(255, 255, 255)
LABEL_BACKGROUND = QColor(0, 0, 0, 150)
LABEL_OFFSET_PX = (8.0, -20.0)  # a label's top-left corner from its anchor, screen px


def cosmetic_pen(colour: QColor, width_px: float = PEN_PX, dashed: bool = False) -> QPen:
    """A pen of constant on-screen width."""
    pen = QPen(colour, width_px)
    pen.setCosmetic(True)
    if dashed:
        pen.setStyle(Qt.PenStyle.DashLine)
    return pen


def _point(uv: np.ndarray) -> QPointF:
    return QPointF(float(uv[0]), float(uv[1]))


class HandleListener(Protocol):
    """Receives the mouse gestures on handles, positions in scene (image pixel) coordinates."""

    def handle_pressed(self, handle: "HandleItem", scene_pos: QPointF) -> None: ...

    def handle_dragged(self, handle: "HandleItem", scene_pos: QPointF) -> None: ...

    def handle_released(self, handle: "HandleItem") -> None: ...

    def handle_removed(self, handle: "HandleItem") -> None: ...  # right press


class HandleItem(QGraphicsItem):
    """A handle of constant on-screen size; ``tag`` names what it moves.

    Without a listener it is a ghost: a dashed ring, fainter, not interactive.
    """

    def __init__(self, parent: QGraphicsItem, tag: Hashable,
                 listener: HandleListener | None) -> None:
        super().__init__(parent)
        self.tag = tag
        self._listener = listener
        self._style = HandleStyle()
        self._colour = QColor(self._style.midline_colour)
        self._selected = False
        self.setFlag(QGraphicsItem.GraphicsItemFlag.ItemIgnoresTransformations)
        if listener is None:
            self.setAcceptedMouseButtons(Qt.MouseButton.NoButton)
        else:
            self.setAcceptedMouseButtons(Qt.MouseButton.LeftButton | Qt.MouseButton.RightButton)
            self.setCursor(Qt.CursorShape.SizeAllCursor)

    def set_look(self, style: HandleStyle, colour: str, selected: bool = False) -> None:
        if style.size_px != self._style.size_px:
            self.prepareGeometryChange()
        self._style, self._colour, self._selected = style, QColor(colour), selected
        self.setOpacity(style.opacity * (GHOST_OPACITY if self._listener is None else 1.0))
        self.update()

    def _radius(self) -> float:
        return self._style.size_px / 2

    def boundingRect(self) -> QRectF:  # noqa: N802 (Qt's name)
        r = self._radius() + SELECTED_GAP_PX + 2 * PEN_PX * SELECTED_PEN_SCALE
        return QRectF(-r, -r, 2 * r, 2 * r)

    def shape(self) -> QPainterPath:
        """The whole disc, open centre included, takes clicks."""
        path = QPainterPath()
        path.addEllipse(QPointF(), self._radius(), self._radius())
        return path

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem,
              widget: QWidget | None = None) -> None:
        r = self._radius()
        ghost = self._listener is None
        path = QPainterPath()
        if ghost or self._style.shape == "ring":
            path.addEllipse(QPointF(), r, r)
        else:
            gap = OPEN_CENTRE * r
            for du, dv in ((1, 0), (-1, 0), (0, 1), (0, -1)):
                path.moveTo(du * gap, dv * gap)
                path.lineTo(du * r, dv * r)
        width = PEN_PX * (SELECTED_PEN_SCALE if self._selected else 1.0)
        if self._selected:
            path.addEllipse(QPointF(), r + SELECTED_GAP_PX, r + SELECTED_GAP_PX)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)
        painter.strokePath(path, cosmetic_pen(HALO, width + 2, ghost))
        painter.strokePath(path, cosmetic_pen(self._colour, width, ghost))

    def mousePressEvent(self, event: QGraphicsSceneMouseEvent) -> None:  # noqa: N802
        if event.button() == Qt.MouseButton.RightButton:
            self._listener.handle_removed(self)
        else:
            self._listener.handle_pressed(self, event.scenePos())
        event.accept()

    def mouseMoveEvent(self, event: QGraphicsSceneMouseEvent) -> None:  # noqa: N802
        self._listener.handle_dragged(self, event.scenePos())

    def mouseReleaseEvent(self, event: QGraphicsSceneMouseEvent) -> None:  # noqa: N802
        self._listener.handle_released(self)


class LabelItem(QGraphicsSimpleTextItem):
    """A small text of constant on-screen size on a dark background, beside its anchor."""

    def __init__(self, parent: QGraphicsItem, text: str = "") -> None:
        super().__init__(text, parent)
        self.setFlag(QGraphicsItem.GraphicsItemFlag.ItemIgnoresTransformations)
        self.setAcceptedMouseButtons(Qt.MouseButton.NoButton)
        self.setBrush(LABEL_COLOUR)
        self.setTransform(QTransform.fromTranslate(*LABEL_OFFSET_PX))

    def paint(self, painter: QPainter, option: QStyleOptionGraphicsItem,
              widget: QWidget | None = None) -> None:
        painter.fillRect(self.boundingRect(), LABEL_BACKGROUND)
        super().paint(painter, option, widget)


def _hide(items: Iterable[QGraphicsItem]) -> None:
    for item in items:
        item.setVisible(False)


def _curve_path(midline_px: np.ndarray) -> QPainterPath:
    """The interpolating midline spline as a dense polyline."""
    spline = midline_spline(midline_px)
    params = np.linspace(spline.x[0], spline.x[-1],
                         CURVE_SAMPLES_PER_SPAN * (len(midline_px) - 1) + 1)
    path = QPainterPath()
    path.addPolygon(QPolygonF([_point(uv) for uv in spline(params)]))
    return path


def _edge_drawn(m: Measurement, station: int, side: int) -> bool:
    """Whether a width handle is drawn: needed, placed, at a measurable station."""
    return (side in m.needed_sides() and not m.skipped[station]
            and bool(np.isfinite(m.offsets_px[station, side])))


class MeasurementItems:
    """Every item that draws one measurement, made once and then updated in place, so that a
    handle being dragged survives the redraw its own edit causes."""

    def __init__(self, scene: QGraphicsScene, listener: HandleListener) -> None:
        self._listener = listener
        self._root = QGraphicsPathItem()  # draws nothing: shows or hides the whole overlay
        self._root.setFlag(QGraphicsItem.GraphicsItemFlag.ItemHasNoContents)
        self._root.setZValue(OVERLAY_Z)
        scene.addItem(self._root)
        # Siblings stack in creation order: lines below handles, labels on top.
        self._lines = [QGraphicsLineItem(self._root) for _ in range(NUM_STATIONS)]
        self._curve = QGraphicsPathItem(self._root)
        self._ghosts = [HandleItem(self._root, ("ghost", s), None) for s in range(NUM_STATIONS)]
        self._edges = [[HandleItem(self._root, ("edge", s, side), listener) for side in (0, 1)]
                       for s in range(NUM_STATIONS)]
        self._points: list[HandleItem] = []  # midline handles, grown as needed, never deleted
        self._ends = (LabelItem(self._root, "rostrum"), LabelItem(self._root, "notch"))
        self._skip_labels = [LabelItem(self._root, "skip") for _ in range(NUM_STATIONS)]
        self._station_label = LabelItem(self._root)
        r = MARKER_RADIUS_PX
        self._marker = QGraphicsEllipseItem(-r, -r, 2 * r, 2 * r, self._root)
        self._marker.setFlag(QGraphicsItem.GraphicsItemFlag.ItemIgnoresTransformations)
        self._marker.setAcceptedMouseButtons(Qt.MouseButton.NoButton)
        self._marker.setPen(cosmetic_pen(HALO))

    def hide(self) -> None:
        self._root.setVisible(False)

    def draw(self, m: Measurement, stations: Stations | None, style: HandleStyle, *,
             widths: bool, point: int | None, edge: tuple[int, int] | None) -> None:
        """Show ``m``. Length mode (``widths`` False): the midline and its points, ``point``
        selected. Widths mode: the midline, stations and edge handles, ``edge`` (station,
        side) selected."""
        self._root.setVisible(True)
        self._draw_midline(m.midline_px, style, None if widths else point, not widths)
        if widths and stations is not None:
            self._draw_stations(m, stations, style, edge)
        else:
            _hide([*self._lines, *self._skip_labels, *self._ghosts,
                   *(h for pair in self._edges for h in pair), self._station_label,
                   self._marker])

    def _draw_midline(self, midline_px: np.ndarray, style: HandleStyle, selected: int | None,
                      show_points: bool) -> None:
        n = len(midline_px)
        self._curve.setPen(cosmetic_pen(QColor(style.midline_colour)))
        self._curve.setPath(_curve_path(midline_px) if n >= 2 else QPainterPath())
        while len(self._points) < n:
            self._points.append(HandleItem(self._root, ("midline", len(self._points)),
                                           self._listener))
        for i, handle in enumerate(self._points):
            handle.setVisible(show_points and i < n)
            if show_points and i < n:
                handle.setPos(_point(midline_px[i]))
                handle.set_look(style, style.midline_colour, i == selected)
        for label, idx, needed in zip(self._ends, (0, -1), (1, 2)):
            label.setVisible(n >= needed)
            if n >= needed:
                label.setPos(_point(midline_px[idx]))

    def _draw_stations(self, m: Measurement, stations: Stations, style: HandleStyle,
                       edge: tuple[int, int] | None) -> None:
        half = PERPENDICULAR_HALF_LENGTH * stations.length_px
        mirrored = m.needed_sides() if m.mirror_side is not None else []
        for s in range(NUM_STATIONS):
            point, normal = stations.points_px[s], stations.normals[s]
            skipped = bool(m.skipped[s])
            line = self._lines[s]
            line.setLine(*(point + half * normal), *(point - half * normal))
            if skipped:
                line.setPen(cosmetic_pen(SKIPPED_COLOUR, dashed=True))
            else:
                selected = edge is not None and edge[0] == s
                line.setPen(cosmetic_pen(SELECTED_LINE_COLOUR if selected else LINE_COLOUR,
                                         PEN_PX if selected else 1.0))
            line.setVisible(True)
            self._skip_labels[s].setVisible(skipped)
            self._skip_labels[s].setPos(_point(point - half * normal))
            for side, handle in enumerate(self._edges[s]):
                drawn = _edge_drawn(m, s, side)
                handle.setVisible(drawn)
                if drawn:
                    handle.setPos(_point(point + m.offsets_px[s, side] * normal))
                    handle.set_look(style, style.side_colour(side), (s, side) == edge)
            ghost = self._ghosts[s]
            ghost_drawn = bool(mirrored) and _edge_drawn(m, s, mirrored[0])
            ghost.setVisible(ghost_drawn)
            if ghost_drawn:
                ghost.setPos(_point(point - m.offsets_px[s, mirrored[0]] * normal))
                ghost.set_look(style, style.side_colour(mirrored[0]))
        self._draw_selection(m, stations, style, edge)

    def _draw_selection(self, m: Measurement, stations: Stations, style: HandleStyle,
                        edge: tuple[int, int] | None) -> None:
        """The selected station's label, and a dot on the midline if its handle is not drawn."""
        self._station_label.setVisible(edge is not None)
        self._marker.setVisible(edge is not None and not _edge_drawn(m, *edge))
        if edge is None:
            return
        s, side = edge
        point = stations.points_px[s]
        end = point + PERPENDICULAR_HALF_LENGTH * stations.length_px * stations.normals[s]
        self._station_label.setText(f"{STATION_PCT[s]:g} %")
        self._station_label.setPos(_point(end))
        self._marker.setPos(_point(point))
        self._marker.setBrush(QColor(style.side_colour(side)))
