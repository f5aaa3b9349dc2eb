"""Checks that an output path can be written before any work is done: a file must not be a
folder, a folder must not be a file, and neither may lie under a file."""

from pathlib import Path

from dolphinfit.core.errors import InputError


def _check_parents(path: Path, where: str) -> None:
    """InputError if the nearest existing ancestor of ``path`` is not a folder."""
    for parent in path.parents:
        if parent.exists():
            if not parent.is_dir():
                raise InputError(f"{where}{path}: lies under {parent}, which is a file, not "
                                 "a folder")
            return


def check_output_file(path: Path, what: str = "") -> Path:
    """``path`` if a file can be written there; InputError naming it (after ``what``, e.g.
    "--out ") otherwise."""
    path = Path(path)
    _check_parents(path, what)
    if path.is_dir():
        raise InputError(f"{what}{path}: is a folder; give a file name")
    return path


def check_output_folder(path: Path, what: str = "") -> Path:
    """``path`` if a folder can be written there; InputError naming it otherwise."""
    path = Path(path)
    _check_parents(path, what)
    if path.exists() and not path.is_dir():
        raise InputError(f"{what}{path}: is a file, not a folder")
    return path
