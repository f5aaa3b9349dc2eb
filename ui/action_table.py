"""The app's actions, menus and keyboard shortcuts, from one data file
(resources/ui/actions.json); the window builds its menus from it and Help → Keyboard
shortcuts lists it, so the two cannot disagree."""

from dataclasses import dataclass

from core.io.json_file import read_json
from core.resources import resource_path

ACTIONS_FILE = ("ui", "actions.json")


@dataclass(frozen=True)
class ActionSpec:
    """One action: its name (the window's handler is ``on_<name>``), menu, label, key.

    ``scope``: "window", or "canvas" for keys that act on the frame's measurement and so
    must not take the arrows, Tab or Delete from the project tree and the settings.
    """

    name: str
    menu: str
    label: str
    shortcut: str = ""
    checkable: bool = False
    scope: str = "window"


def load_action_table() -> tuple[list[str], list[ActionSpec]]:
    """The menus in order and every action in menu order."""
    data = read_json(resource_path(*ACTIONS_FILE), "the action table")
    return list(data["menus"]), [ActionSpec(**entry) for entry in data["actions"]]
