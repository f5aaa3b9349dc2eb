"""The app's actions, menus and keyboard shortcuts, from one data file
(resources/ui/actions.json), and the mouse gestures on the frame; the window builds its menus
from it, and Help → Keyboard shortcuts and the manual's reference list it, so none can
disagree. No Qt here: the manual is built without it."""

from dataclasses import dataclass

from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.resources import resource_path

ACTIONS_FILE = ("ui", "actions.json")
CTRL = "{ctrl}"  # replaced by the platform's name of the Ctrl modifier (⌘ on macOS)
MOUSE_GESTURES = (   # on the frame: (gesture, what it does)
    ("Wheel", "Zoom in or out at the cursor"),
    ("Middle-drag, Space+drag", "Pan"),
    ("Left click", "Place a length point or a width handle"),
    ("Drag", "Move a handle"),
    ("Right click", "Delete a length point"),
    (f"{CTRL}click", "Insert a length point"),
)


@dataclass(frozen=True)
class ActionSpec:
    """One action: its name (the window's handler is ``on_<name>``), menu (and submenu),
    label, key.

    ``scope``: "window", or "canvas" for keys that act on the frame's measurement and so
    must not take the arrows, Tab or Delete from the project tree and the settings.
    """

    name: str
    menu: str
    label: str
    shortcut: str = ""
    checkable: bool = False
    scope: str = "window"
    submenu: str = ""   # a submenu of ``menu`` the action sits in (e.g. "Compute device")

    @property
    def where(self) -> str:
        """Its menu, and submenu where it has one ("Edit → Compute device")."""
        return f"{self.menu} → {self.submenu}" if self.submenu else self.menu


def load_action_table() -> tuple[list[str], list[ActionSpec]]:
    """The menus in order and every action in menu order."""
    data = read_json(resource_path(*ACTIONS_FILE), "the action table")
    return list(data["menus"]), [ActionSpec(**entry) for entry in data["actions"]]
