"""How the measuring handles look: on-screen size, colours, opacity and shape (a user setting).

The default colours stay readable on blue-green water and on grey dolphins. The default cross
has an open centre, so the body edge under a handle stays visible: MorphoMetriX's crosshair hid
the opposite edge on narrow dolphin tail stocks (reference/ecosystem.md §1, issue #17).
"""

from dataclasses import dataclass

from PySide6.QtGui import QColor

HANDLE_SHAPES = ("cross", "ring")


@dataclass(frozen=True)
class HandleStyle:
    """``size_px``: a handle's extent on screen, in screen pixels at any zoom. Colours are
    names Qt reads ("#ffd400", "yellow"). ``opacity``: 0 (invisible) to 1. ``shape``: "cross"
    (thin arms around an open centre) or "ring"."""

    size_px: float = 17.0
    side_a_colour: str = "#ffd400"  # yellow
    side_b_colour: str = "#00e5ff"  # cyan
    midline_colour: str = "#ff40ff"  # magenta
    opacity: float = 0.9
    shape: str = "cross"

    def __post_init__(self) -> None:
        if not self.size_px > 0:
            raise ValueError(f"handle size must be > 0 screen px, got {self.size_px!r}")
        if not 0 < self.opacity <= 1:
            raise ValueError(f"handle opacity must be in (0, 1], got {self.opacity!r}")
        if self.shape not in HANDLE_SHAPES:
            raise ValueError(f"handle shape must be one of {HANDLE_SHAPES}, got {self.shape!r}")
        for name in ("side_a_colour", "side_b_colour", "midline_colour"):
            if not QColor(getattr(self, name)).isValid():
                raise ValueError(f"{name} is not a colour: {getattr(self, name)!r}")

    def side_colour(self, side: int) -> str:
        """The colour of side A (0) or side B (1)."""
        return (self.side_a_colour, self.side_b_colour)[side]
