"""The measuring overlay: draws the current measurement on the frame view and turns mouse and
keyboard input into undoable edits (core/project/edits.py through ui/state/commands.py).

Length mode: a click appends a midline point (rostrum tip first, fluke notch last), Ctrl+click
inserts one on the nearest segment; points drag; a right click or Delete removes one.
Widths mode: every station has a side A and a side B handle on its perpendicular. A click
places the selected handle at the click's projection and selects the next unplaced one;
handles drag along their perpendicular; Up/Down nudge the selected one outward/inward.

Keys consumed while the measurement is shown on the canvas (the window owns all others;
Left/Right always step frames): Delete/Backspace in both modes (a selected point or edge);
in widths mode also Tab, Shift+Tab and Up/Down (plain, Alt: fine, Shift: coarse).
"""

from collections.abc import Callable, Hashable
from dataclasses import dataclass
from functools import partial

import numpy as np
from PySide6.QtCore import QEvent, QObject, QPointF, QRectF, Qt, Signal
from PySide6.QtGui import QKeyEvent

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation import SIDES, Stations
from dolphinfit.core.measure.mask_midline import suggested_edges
from dolphinfit.core.measure.stations import NUM_STATIONS, STATION_PCT
from dolphinfit.core.project import edits
from dolphinfit.core.project.model import Measurement
from dolphinfit.ui.widgets.canvas import FrameCanvas
from dolphinfit.ui.state.commands import edit_measurement
from dolphinfit.ui.state.handle_style import HandleStyle
from dolphinfit.ui.widgets.overlay_items import HandleItem, MeasurementItems
from dolphinfit.ui.state.project_model import Change, ProjectModel

MODES = ("length", "widths")
NUDGE_PX = 1.0  # arrow key, image px along the perpendicular
FINE_NUDGE_PX = 0.1  # Alt + arrow
COARSE_NUDGE_PX = 5.0  # Shift + arrow
CLICK_REACH_FRACTION = 0.05  # of body length: a click-to-place lands within one station gap
NUDGE_STEPS = {Qt.KeyboardModifier.NoModifier: NUDGE_PX,
               Qt.KeyboardModifier.AltModifier: FINE_NUDGE_PX,
               Qt.KeyboardModifier.ShiftModifier: COARSE_NUDGE_PX}
AUTO_ZOOM_FRACTION = 0.3  # of body length: the square shown around a station on auto-zoom

Edge = tuple[int, int]  # (station, side), side 0 = A, 1 = B


def handle_order(m: Measurement) -> list[Edge]:
    """Width handles in Tab order: A5, B5, A10, B10, … (only the mirrored side if mirrored)."""
    return [(s, side) for s in range(NUM_STATIONS) for side in m.needed_sides()]


def next_unplaced(m: Measurement, after: Edge | None) -> Edge | None:
    """The first handle after ``after`` in Tab order (wrapping) not yet placed, at a station
    not skipped; None when every edge is done."""
    order = handle_order(m)
    start = order.index(after) + 1 if after in order else 0
    return next((e for e in order[start:] + order[:start]
                 if not m.skipped[e[0]] and np.isnan(m.offsets_px[e])), None)


def _on_own_side(offset_px: float, side: int) -> float:
    """An offset kept on its handle's half of the perpendicular (side A ≥ 0, side B ≤ 0)."""
    return max(offset_px, 0.0) if side == 0 else min(offset_px, 0.0)


def _edge_name(edge: Edge) -> str:
    return f"side {SIDES[edge[1]]} at {STATION_PCT[edge[0]]:g} %"


@dataclass(frozen=True)
class _Drag:
    """A handle drag in progress: handle minus press position (image px) and its undo tag."""

    grab: tuple[float, float]
    merge_tag: Hashable


class MeasureOverlay(QObject):
    """Draws ``model.current_measurement()`` on its frame of ``canvas`` and edits it.

    Redraws on the model's signals only. ``auto_zoom``: zoom to the station whenever the
    selection moves to another handle by key or click.
    """

    status_message = Signal(str)
    selection_changed = Signal(int, int)  # station, side (0 = A, 1 = B); -1, -1 for none

    def __init__(self, canvas: FrameCanvas, model: ProjectModel) -> None:
        super().__init__(canvas)
        self._canvas = canvas
        self._model = model
        self._items = MeasurementItems(canvas.scene(), self)
        self._style = HandleStyle()
        self._mode = "length"
        self._frame_idx: int | None = None
        self._key = model.current_key()
        self._point: int | None = None  # selected midline point
        self._edge: Edge | None = None  # selected width handle
        self._drag: _Drag | None = None
        self._gesture = 0  # drag/nudge serial: edits merge into one undo step within one
        self._own_edit = False
        self._station_cache: tuple[np.ndarray, Stations | None] | None = None
        self.auto_zoom = False
        model.changed.connect(self._on_model_changed)
        model.selection_changed.connect(self._on_selection_changed)
        canvas.image_clicked.connect(self._on_image_clicked)
        canvas.installEventFilter(self)
        self._reset_selection()
        self._redraw()

    # --- state -------------------------------------------------------------------------------

    @property
    def mode(self) -> str:
        return self._mode

    @property
    def style(self) -> HandleStyle:
        return self._style

    @property
    def selected_edge(self) -> Edge | None:
        return self._edge

    @property
    def selected_point(self) -> int | None:
        return self._point

    def set_mode(self, mode: str) -> None:
        """"length" (midline points) or "widths" (edge handles)."""
        if mode not in MODES:
            raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
        self._mode = mode
        self._drag = None
        self._redraw()

    def set_style(self, style: HandleStyle) -> None:
        self._style = style
        self._redraw()

    def set_frame(self, frame_idx: int | None) -> None:
        """The frame the canvas shows: the measurement is drawn on its own frame only."""
        self._frame_idx = frame_idx
        self._drag = None
        self._redraw()

    def _shown(self) -> Measurement | None:
        """The current measurement if it belongs to the shown frame."""
        m = self._model.current_measurement()
        return m if m is not None and m.frame_idx == self._frame_idx else None

    def _stations(self, m: Measurement) -> Stations | None:
        if self._station_cache is None or not np.array_equal(self._station_cache[0],
                                                             m.midline_px):
            self._station_cache = (m.midline_px, edits.stations_of(m))
        return self._station_cache[1]

    def _redraw(self) -> None:
        m = self._shown()
        if m is None:
            self._items.hide()
            return
        self._items.draw(m, self._stations(m), self._style, widths=self._mode == "widths",
                         point=self._point, edge=self._edge)

    # --- selection ---------------------------------------------------------------------------

    def _set_edge(self, edge: Edge | None, zoom: bool = False) -> None:
        if edge != self._edge:
            self._edge = edge
            self._gesture += 1
            self.selection_changed.emit(*(edge if edge is not None else (-1, -1)))
        if zoom:
            self._zoom_to_selection()

    def _reset_selection(self) -> None:
        """First unplaced handle (else A5) of a newly current measurement; no point."""
        self._point = None
        m = self._model.current_measurement()
        self._set_edge(None if m is None else next_unplaced(m, None) or handle_order(m)[0])

    def _clamp_selection(self) -> None:
        """Keep the selection valid after an undo, redo or another view's edit."""
        m = self._model.current_measurement()
        if m is None:
            return
        if self._point is not None and self._point >= len(m.midline_px):
            self._point = None
        if self._edge is not None and self._edge[1] not in m.needed_sides():
            self._set_edge((self._edge[0], m.needed_sides()[0]))

    def _zoom_to_selection(self) -> None:
        m = self._shown()
        stations = None if m is None else self._stations(m)
        if not self.auto_zoom or stations is None or self._edge is None:
            return
        u, v = stations.points_px[self._edge[0]]
        side = AUTO_ZOOM_FRACTION * stations.length_px
        self._canvas.zoom_to(QRectF(u - side / 2, v - side / 2, side, side))

    def _on_selection_changed(self) -> None:
        key = self._model.current_key()
        if key != self._key:
            self._key = key
            self._drag = None
            self._reset_selection()
        self._redraw()

    def _on_model_changed(self, change: Change) -> None:
        if not self._own_edit:  # an undo, redo or other view's edit ends a drag or nudges
            self._gesture += 1
            self._clamp_selection()
        self._redraw()

    # --- edits -------------------------------------------------------------------------------

    def _edit(self, change: Callable[[Measurement], Measurement], text: str,
              merge_tag: Hashable | None = None) -> bool:
        """Apply ``change`` to the shown measurement as an undo step; a refused edit becomes a
        status message. True if applied."""
        m = self._shown()
        if m is None:
            return False
        try:
            new = change(m)
        except ValueError as exc:
            self.status_message.emit(f"{text} refused: {exc}")
            return False
        self._own_edit = True
        try:
            edit_measurement(self._model, self._model.current_key(), new, text, merge_tag)
        finally:
            self._own_edit = False
        return True

    def _place_edge(self, edge: Edge, u: float, v: float, merge_tag: Hashable | None = None,
                    is_move: bool = False) -> bool:
        """Put a width handle at the projection of (u, v) on its perpendicular: by a click,
        or (``is_move``) by a drag (a suggested edge becomes suggested then moved)."""
        m = self._shown()
        stations = None if m is None else self._stations(m)
        if stations is None:
            self.status_message.emit("Draw the length (two midline points or more) first")
            return False
        station, side = edge
        offset = _on_own_side(edits.offset_of_point(stations, station, u, v), side)
        place = edits.move_offset if is_move else edits.set_offset
        return self._edit(lambda m: place(m, station, side, offset),
                          f"Place {_edge_name(edge)}", merge_tag)

    def _delete_point(self, index: int) -> None:
        if self._edit(lambda m: edits.delete_midline_point(m, index), "Delete midline point"):
            self._point = index - 1 if index > 0 else None
            self._redraw()

    def _remove_edge(self, edge: Edge) -> None:
        self._edit(lambda m: edits.set_offset(m, *edge, np.nan), f"Remove {_edge_name(edge)}")

    def delete_selected_point(self) -> None:
        """Length mode: delete the selected midline point; widths mode: remove the selected
        edge (its handle goes back to unplaced)."""
        m = self._shown()
        if m is None:
            return
        if self._mode == "length" and self._point is not None:
            self._delete_point(self._point)
        elif (self._mode == "widths" and self._edge is not None
              and np.isfinite(m.offsets_px[self._edge])):
            self._remove_edge(self._edge)

    def reverse_direction(self) -> None:
        """Swap the rostrum and notch ends; every edge stays where it is on the image."""
        m = self._shown()
        if m is None or not self._edit(edits.reverse_midline, "Reverse midline direction"):
            return
        if self._point is not None:
            self._point = len(m.midline_px) - 1 - self._point
        if self._edge is not None:
            self._set_edge((NUM_STATIONS - 1 - self._edge[0], 1 - self._edge[1]))
        self._redraw()

    def set_mirror_side(self, side: str | None) -> None:
        """Measure both sides (None) or one side ("A" or "B") and double it."""
        if self._edit(lambda m: edits.set_mirror_side(m, side),
                      "Measure both sides" if side is None else f"Mirror side {side}"):
            self._clamp_selection()
            self._redraw()

    def skip_station(self) -> None:
        """Mark the selected station not measurable and move on; on a skipped station, measure
        it again."""
        m = self._shown()
        if m is None or self._edge is None:
            return
        station = self._edge[0]
        name = f"station {STATION_PCT[station]:g} %"
        if m.skipped[station]:
            self._edit(lambda m: edits.set_skipped(m, station, False), f"Measure {name} again")
            return
        if not self._edit(lambda m: edits.set_skipped(m, station, True), f"Skip {name}"):
            return
        m = self._shown()
        last = (station, m.needed_sides()[-1])
        following = ((station + 1) % NUM_STATIONS, m.needed_sides()[0])
        self._set_edge(next_unplaced(m, last) or following, zoom=True)
        self._redraw()

    def next_handle(self) -> None:
        self._step_handle(1)

    def previous_handle(self) -> None:
        self._step_handle(-1)

    def _step_handle(self, step: int) -> None:
        m = self._shown()
        if m is None:
            return
        order = handle_order(m)
        index = order.index(self._edge) if self._edge in order else (-1 if step > 0 else 0)
        self._set_edge(order[(index + step) % len(order)], zoom=True)
        self._redraw()

    def nudge(self, direction: int, step_px: float = NUDGE_PX) -> None:
        """Move the selected handle along its perpendicular by ``step_px`` image px, outward
        from the midline (``direction`` +1) or inward (−1), never across it."""
        m = self._shown()
        if m is None or self._edge is None:
            return
        station, side = self._edge
        offset = m.offsets_px[station, side]
        if np.isnan(offset):
            self.status_message.emit(f"{_edge_name(self._edge)} is not placed yet: "
                                     "click its edge first")
            return
        outward = 1.0 if side == 0 else -1.0  # side A lies at positive offsets
        new = _on_own_side(offset + direction * outward * step_px, side)
        self._edit(lambda m: edits.move_offset(m, station, side, new),
                   f"Nudge {_edge_name(self._edge)}",
                   ("nudge", station, side, self._key, self._gesture))

    def suggest_edges(self, mask: np.ndarray) -> bool:
        """Fill the unplaced edges where the perpendiculars leave ``mask`` ((H, W) bool of the
        shown frame), as one undo step; placed edges stay. True if applied."""
        m = self._shown()
        stations = None if m is None else self._stations(m)
        if stations is None:
            self.status_message.emit("Draw the length (two midline points or more) before "
                                     "suggesting edges")
            return False
        rect = self._canvas.image_rect()
        frame_shape = (round(rect.height()), round(rect.width()))
        if np.shape(mask) != frame_shape:
            raise InputError(f"mask: {'×'.join(map(str, np.shape(mask)[::-1]))} px, but the "
                             f"frame is {frame_shape[1]}×{frame_shape[0]} px (width×height)")
        suggested = suggested_edges(np.asarray(mask), stations)
        placed = np.isfinite(m.offsets_px).sum()
        if not self._edit(lambda m: edits.offsets_from_edges(m, suggested),
                          "Suggest edges from the mask"):
            return False
        added = np.isfinite(self._shown().offsets_px).sum() - placed
        self.status_message.emit(f"{added} edges suggested from the mask: review them")
        return True

    # --- mouse -------------------------------------------------------------------------------

    def _on_image_clicked(self, u: float, v: float, modifiers: Qt.KeyboardModifier) -> None:
        m = self._shown()
        if m is None:
            self.status_message.emit("No measurement on this frame")
        elif self._mode == "widths":
            self._click_edge(u, v)
        elif modifiers & Qt.KeyboardModifier.ControlModifier and m.has_length:
            index = edits.nearest_segment(m, u, v)
            if self._edit(lambda m: edits.insert_midline_point(m, index, u, v),
                          "Insert midline point"):
                self._point = index
                self._redraw()
        elif self._edit(lambda m: edits.add_midline_point(m, u, v), "Add midline point"):
            self._point = len(m.midline_px)
            self._redraw()

    def _click_edge(self, u: float, v: float) -> None:
        """Click-to-place: the selected handle goes to the click, the next unplaced one is
        selected. A click far along the body from the selected station's line (more than
        CLICK_REACH_FRACTION of the body length) is taken for a stray click and refused."""
        if self._edge is None:
            return
        stations = self._stations(self._shown())
        if stations is None:
            return
        station = self._edge[0]
        normal = stations.normals[station]
        along = np.dot(np.array([u, v]) - stations.points_px[station], [normal[1], -normal[0]])
        if abs(along) > CLICK_REACH_FRACTION * stations.length_px:
            self.status_message.emit(f"Click nearer the line of {_edge_name(self._edge)} to "
                                     "place that edge")
            return
        if not self._place_edge(self._edge, u, v):
            return
        following = next_unplaced(self._shown(), self._edge)
        if following is None:
            self.status_message.emit("Every width edge is placed")
        else:
            self._set_edge(following, zoom=True)
        self._redraw()

    def handle_pressed(self, handle: HandleItem, scene_pos: QPointF) -> None:
        kind, *index = handle.tag
        if kind == "midline":
            self._point = index[0]
        else:
            self._set_edge(tuple(index))
        self._gesture += 1
        grab = handle.pos() - scene_pos
        self._drag = _Drag((grab.x(), grab.y()), (*handle.tag, self._key, self._gesture))
        self._redraw()

    def handle_dragged(self, handle: HandleItem, scene_pos: QPointF) -> None:
        if self._drag is None:
            return
        u, v = scene_pos.x() + self._drag.grab[0], scene_pos.y() + self._drag.grab[1]
        kind, *index = handle.tag
        if kind == "midline":
            self._edit(lambda m: edits.move_midline_point(m, index[0], u, v),
                       "Move midline point", self._drag.merge_tag)
        else:
            self._place_edge(tuple(index), u, v, self._drag.merge_tag, is_move=True)

    def handle_released(self, handle: HandleItem) -> None:
        self._drag = None

    def handle_removed(self, handle: HandleItem) -> None:
        kind, *index = handle.tag
        if kind == "midline":
            self._delete_point(index[0])
        else:
            self._remove_edge(tuple(index))

    # --- keys --------------------------------------------------------------------------------

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:  # noqa: N802 (Qt's name)
        if event.type() not in (QEvent.Type.KeyPress, QEvent.Type.ShortcutOverride):
            return False
        action = self._key_action(event)
        if action is None:
            return False
        if event.type() == QEvent.Type.KeyPress:
            action()
        event.accept()  # a ShortcutOverride accepted keeps window shortcuts off this key
        return True

    def _key_action(self, event: QKeyEvent) -> Callable[[], None] | None:
        """What a key does on the canvas; None leaves it to the window."""
        if self._shown() is None:
            return None
        key = event.key()
        modifiers = event.modifiers() & ~Qt.KeyboardModifier.KeypadModifier
        widths = self._mode == "widths"
        if key in (Qt.Key.Key_Delete, Qt.Key.Key_Backspace) and not modifiers:
            selected = self._edge if widths else self._point
            return self.delete_selected_point if selected is not None else None
        if not widths:
            return None
        if key == Qt.Key.Key_Tab and not modifiers:
            return self.next_handle
        if key == Qt.Key.Key_Backtab:
            return self.previous_handle
        if key in (Qt.Key.Key_Up, Qt.Key.Key_Down) and modifiers in NUDGE_STEPS:
            return partial(self.nudge, 1 if key == Qt.Key.Key_Up else -1, NUDGE_STEPS[modifiers])
        return None
