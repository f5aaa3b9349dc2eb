"""The user's app preferences (handle style, auto-zoom), a JSON file in the config folder."""

from typing import Any

from dolphinfit.core.camera_presets import config_dir
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.json_file import read_json, write_json

PREFERENCES_FILE = "preferences.json"


def load_preferences() -> dict[str, Any]:
    """The stored preferences; an unreadable file counts as none."""
    path = config_dir() / PREFERENCES_FILE
    if not path.exists():
        return {}
    try:
        data = read_json(path, "the preferences")
    except InputError:
        return {}
    return data if isinstance(data, dict) else {}


def save_preference(key: str, value: Any) -> None:
    """Store one preference."""
    data = load_preferences()
    data[key] = value
    write_json(config_dir() / PREFERENCES_FILE, data)
