"""The width handles' look: size on screen, a colour per side, opacity and shape."""

from dataclasses import replace

from PySide6.QtGui import QColor, QIcon, QPixmap
from PySide6.QtWidgets import (QColorDialog, QComboBox, QDialog, QFormLayout, QPushButton,
                               QSpinBox, QVBoxLayout, QWidget)

from dolphinfit.ui.dialogs.dialog_buttons import ok_cancel_buttons
from dolphinfit.ui.state.handle_style import HandleStyle

SIZE_RANGE_PX = (6, 60)
OPACITY_RANGE_PCT = (10, 100)
SHAPES = {"cross": "Thin cross, open centre", "ring": "Ring"}
SWATCH_PX = 16


class ColourButton(QPushButton):
    """A button showing a colour (swatch and #rrggbb); a click opens the colour picker."""

    def __init__(self, colour: str, title: str, parent: QWidget | None = None,
                 **qt_properties: object) -> None:
        super().__init__(parent, **qt_properties)
        self._title = title
        self.clicked.connect(self._pick)
        self.set_colour(QColor(colour))

    def set_colour(self, colour: QColor) -> None:
        self._colour = colour
        swatch = QPixmap(SWATCH_PX, SWATCH_PX)
        swatch.fill(colour)
        self.setIcon(QIcon(swatch))
        self.setText(colour.name())

    def _pick(self) -> None:
        colour = QColorDialog.getColor(self._colour, self, self._title)
        if colour.isValid():
            self.set_colour(colour)

    @property
    def colour(self) -> str:
        """The colour as "#rrggbb"."""
        return self._colour.name()


class HandleStyleDialog(QDialog):
    """Edit a handle style; ``style`` is the result (the midline colour is kept)."""

    def __init__(self, style: HandleStyle, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Handle style")
        self._start = style
        self._size = QSpinBox(objectName="size_px", suffix=" px on screen")
        self._size.setRange(*SIZE_RANGE_PX)
        self._size.setValue(round(style.size_px))
        self._colour_a = ColourButton(style.side_a_colour, "Side A colour", objectName="colour_a")
        self._colour_b = ColourButton(style.side_b_colour, "Side B colour", objectName="colour_b")
        self._opacity = QSpinBox(objectName="opacity", suffix=" %")
        self._opacity.setRange(*OPACITY_RANGE_PCT)
        self._opacity.setValue(round(style.opacity * 100))
        self._shape = QComboBox(objectName="shape")
        for key, label in SHAPES.items():
            self._shape.addItem(label, key)
        self._shape.setCurrentIndex(max(self._shape.findData(style.shape), 0))
        form = QFormLayout()
        for label, widget in (("Size:", self._size), ("Side A:", self._colour_a),
                              ("Side B:", self._colour_b), ("Opacity:", self._opacity),
                              ("Shape:", self._shape)):
            form.addRow(label, widget)
        buttons = ok_cancel_buttons(self)
        layout = QVBoxLayout(self)
        layout.addLayout(form)
        layout.addWidget(buttons)

    @property
    def style(self) -> HandleStyle:
        """The edited style."""
        return replace(self._start, size_px=float(self._size.value()),
                       side_a_colour=self._colour_a.colour, side_b_colour=self._colour_b.colour,
                       opacity=self._opacity.value() / 100, shape=self._shape.currentData())
