"""The frame view: one video frame with overlay items, zoom about the cursor and panning.

Scene coordinates are image pixel coordinates (core/camera.py): pixel centres at integers,
u right, v down, so pixel (0, 0) covers the scene square [-0.5, 0.5)². The frame is the
pixmap item at z = 0; overlays are items added to ``canvas.scene()`` at z > 0.
"""

import numpy as np
from PySide6.QtCore import QEvent, QPointF, QRectF, Qt, Signal
from PySide6.QtGui import (QColor, QFocusEvent, QKeyEvent, QMouseEvent, QPainter, QPixmap,
                           QResizeEvent, QWheelEvent)
from PySide6.QtWidgets import QGraphicsPixmapItem, QGraphicsScene, QGraphicsView, QWidget

from dolphinfit.ui.workers.frame_loader import rgb_to_qimage

ZOOM_STEP = 1.15  # scale factor per wheel notch
WHEEL_NOTCH = 120  # angleDelta units per notch
MIN_ZOOM_OF_FIT = 0.25  # zooming out stops at this fraction of the fit-to-window scale
MAX_SCALE = 64.0  # screen pixels per image pixel
BACKGROUND = QColor(32, 32, 32)


class FrameCanvas(QGraphicsView):
    """Shows one frame; keeps zoom and pan across frames of the same size.

    Wheel zooms about the cursor; middle-drag or Space + left-drag pans. A first frame, or one
    of a new size, fits to the window, and keeps fitting on resizes until the user zooms or pans.
    """

    image_clicked = Signal(float, float, Qt.KeyboardModifier)  # u, v (image px), modifiers
    cursor_moved = Signal(float, float)  # u, v (image px) under the cursor
    space_tapped = Signal()  # Space pressed and released without panning

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setScene(QGraphicsScene(self))
        self._pixmap_item = QGraphicsPixmapItem()
        self._pixmap_item.setOffset(-0.5, -0.5)
        self._pixmap_item.setTransformationMode(Qt.TransformationMode.SmoothTransformation)
        self._pixmap_item.setZValue(0)
        self.scene().addItem(self._pixmap_item)
        self._image_size: tuple[int, int] | None = None  # (width, height) of the shown frame
        self._auto_fit = True  # refit on resize until the user zooms or pans
        self._space_held = False
        self._panned_while_space = False
        self._pan_from: QPointF | None = None  # viewport position of the last pan step
        self.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.setVerticalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.setTransformationAnchor(QGraphicsView.ViewportAnchor.NoAnchor)
        self.setResizeAnchor(QGraphicsView.ViewportAnchor.NoAnchor)
        self.setRenderHints(QPainter.RenderHint.Antialiasing
                            | QPainter.RenderHint.SmoothPixmapTransform)
        self.setBackgroundBrush(BACKGROUND)
        self.setFrameShape(QGraphicsView.Shape.NoFrame)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.viewport().setMouseTracking(True)

    # --- frame -------------------------------------------------------------------------------

    def set_frame(self, rgb: np.ndarray) -> None:
        """Show an (H, W, 3) uint8 RGB frame; the zoom and pan stay unless its size changed."""
        pixmap = QPixmap.fromImage(rgb_to_qimage(rgb))
        self._pixmap_item.setPixmap(pixmap)
        size = (pixmap.width(), pixmap.height())
        if size != self._image_size:
            self._image_size = size
            self.fit_to_window()

    def image_rect(self) -> QRectF:
        """The shown frame's extent in scene (image pixel) coordinates; empty if none."""
        if self._image_size is None:
            return QRectF()
        return QRectF(-0.5, -0.5, *self._image_size)

    # --- zoom and pan ------------------------------------------------------------------------

    def view_scale(self) -> float:
        """Screen pixels per image pixel."""
        return self.transform().m11()

    def fit_to_window(self) -> None:
        """Scale the whole frame to fit the view, centred; it refits on resizes from now on."""
        self.zoom_to(self.image_rect())
        self._auto_fit = True

    def zoom_to(self, rect: QRectF) -> None:
        """Scale so that ``rect`` (image px) just fits the view, centred on it (scale clamped)."""
        if rect.isEmpty() or self._image_size is None:
            return
        self._auto_fit = False
        viewport = QRectF(self.viewport().rect())
        scale = min(viewport.width() / rect.width(), viewport.height() / rect.height())
        self._set_scale(scale, rect.center(), viewport.center())

    def zoom_by(self, factor: float, anchor: QPointF) -> None:
        """Multiply the scale by ``factor``, keeping the image point at viewport ``anchor``."""
        if self._image_size is None:
            return
        self._auto_fit = False
        self._set_scale(self.view_scale() * factor, self._to_scene(anchor), anchor)

    def _set_scale(self, scale: float, scene_point: QPointF, viewport_point: QPointF) -> None:
        """Set the scale (clamped) and scroll ``scene_point`` to ``viewport_point``."""
        if self.viewport().rect().isEmpty():
            return
        scale = min(max(scale, self._min_scale()), MAX_SCALE)
        self.resetTransform()
        self.scale(scale, scale)
        self._update_scene_rect()
        self._scroll_by(self.viewportTransform().map(scene_point) - viewport_point)

    def _min_scale(self) -> float:
        width, height = self._image_size
        viewport = self.viewport().rect()
        fit = min(viewport.width() / width, viewport.height() / height)
        return min(MIN_ZOOM_OF_FIT * fit, MAX_SCALE)

    def _update_scene_rect(self) -> None:
        """The image plus one viewport of margin all round, so it can be panned to any edge."""
        scale = self.view_scale()
        margin_u = self.viewport().width() / scale
        margin_v = self.viewport().height() / scale
        self.setSceneRect(self.image_rect().adjusted(-margin_u, -margin_v, margin_u, margin_v))

    def _scroll_by(self, delta: QPointF) -> None:
        """Move the view content by ``-delta`` viewport pixels."""
        hbar, vbar = self.horizontalScrollBar(), self.verticalScrollBar()
        hbar.setValue(hbar.value() + round(delta.x()))
        vbar.setValue(vbar.value() + round(delta.y()))

    def _to_scene(self, viewport_point: QPointF) -> QPointF:
        return self.viewportTransform().inverted()[0].map(viewport_point)

    # --- events ------------------------------------------------------------------------------

    def resizeEvent(self, event: QResizeEvent) -> None:
        super().resizeEvent(event)
        if self._auto_fit:
            self.fit_to_window()
        elif self._image_size is not None:
            self._update_scene_rect()

    def wheelEvent(self, event: QWheelEvent) -> None:
        notches = event.angleDelta().y() / WHEEL_NOTCH
        if notches:
            self.zoom_by(ZOOM_STEP ** notches, event.position())
        event.accept()

    def mousePressEvent(self, event: QMouseEvent) -> None:
        button = event.button()
        if button == Qt.MouseButton.MiddleButton or (
                button == Qt.MouseButton.LeftButton and self._space_held):
            self._pan_from = event.position()
            self.viewport().setCursor(Qt.CursorShape.ClosedHandCursor)
            event.accept()
            return
        super().mousePressEvent(event)
        if button != Qt.MouseButton.LeftButton or event.isAccepted():
            return
        point = self._to_scene(event.position())
        if self.image_rect().contains(point):
            self.image_clicked.emit(point.x(), point.y(), event.modifiers())

    def mouseMoveEvent(self, event: QMouseEvent) -> None:
        point = self._to_scene(event.position())
        self.cursor_moved.emit(point.x(), point.y())
        if self._pan_from is None:
            super().mouseMoveEvent(event)
            return
        self._auto_fit = False
        self._panned_while_space |= self._space_held
        self._scroll_by(self._pan_from - event.position())
        self._pan_from = event.position()
        event.accept()

    def mouseReleaseEvent(self, event: QMouseEvent) -> None:
        if self._pan_from is None:
            super().mouseReleaseEvent(event)
            return
        self._pan_from = None
        self._update_cursor()
        event.accept()

    def event(self, event: QEvent) -> bool:
        # Claim Space before window shortcuts see it: it is the pan modifier here (a tap is
        # re-emitted as ``space_tapped``, e.g. for play/pause).
        if event.type() == QEvent.Type.ShortcutOverride and _is_plain_space(event):
            event.accept()
            return True
        return super().event(event)

    def keyPressEvent(self, event: QKeyEvent) -> None:
        if not _is_plain_space(event):
            super().keyPressEvent(event)
            return
        if not event.isAutoRepeat():
            self._space_held = True
            self._panned_while_space = False
            self._update_cursor()
        event.accept()

    def keyReleaseEvent(self, event: QKeyEvent) -> None:
        if event.key() != Qt.Key.Key_Space:
            super().keyReleaseEvent(event)
            return
        if not event.isAutoRepeat():
            self._space_held = False
            self._update_cursor()
            if not self._panned_while_space:
                self.space_tapped.emit()
        event.accept()

    def focusOutEvent(self, event: QFocusEvent) -> None:
        self._space_held = False
        self._update_cursor()
        super().focusOutEvent(event)

    def _update_cursor(self) -> None:
        if self._pan_from is not None:
            return
        if self._space_held:
            self.viewport().setCursor(Qt.CursorShape.OpenHandCursor)
        else:
            self.viewport().unsetCursor()


def _is_plain_space(event: QKeyEvent) -> bool:
    return event.key() == Qt.Key.Key_Space and event.modifiers() == Qt.KeyboardModifier.NoModifier
