"""Locating the files shipped in the repository's ``resources/`` folder."""

from pathlib import Path

from dolphinfit.core.errors import InputError

RESOURCES_DIR = Path(__file__).resolve().parent.parent / "resources"


def resource_path(*parts: str) -> Path:
    """Path of a shipped resource; raises InputError naming it when it is missing."""
    path = RESOURCES_DIR.joinpath(*parts)
    if not path.exists():
        raise InputError(f"{path}: bundled resource not found (is the repository complete?)")
    return path
