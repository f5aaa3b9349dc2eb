"""The recent-projects list, kept in the user's config folder beside the camera presets."""

from pathlib import Path

from dolphinfit.core.camera_presets import config_dir
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.json_file import read_json, write_json

RECENT_FILE = "recent.json"
MAX_RECENT = 10


def recent_path() -> Path:
    """The file holding the list."""
    return config_dir() / RECENT_FILE


def recent_projects() -> list[Path]:
    """Recently opened projects that still exist, newest first (an unreadable list is empty)."""
    path = recent_path()
    if not path.exists():
        return []
    try:
        data = read_json(path, "the recent-projects list")
    except InputError:
        return []
    entries = data.get("projects", []) if isinstance(data, dict) else []
    return [Path(p) for p in entries if isinstance(p, str) and Path(p).exists()]


def add_recent(project_path: Path) -> list[Path]:
    """Put ``project_path`` first in the list and return the list."""
    project_path = Path(project_path).resolve()
    entries = [project_path] + [p for p in recent_projects() if p != project_path]
    entries = entries[:MAX_RECENT]
    write_json(recent_path(), {"projects": [str(p) for p in entries]})
    return entries
