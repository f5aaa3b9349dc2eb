"""Atomic writes: a file or a whole folder is written beside its target, then swapped in, so a
kill at any moment leaves either the old or the new complete output."""

import ctypes
import os
import re
import shutil
import sys
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.output_paths import check_output_file, check_output_folder

FILE_MODE = 0o644  # mkstemp creates 0600; written files should read like any other
FOLDER_MODE = 0o755  # mkdtemp creates 0700
_AT_FDCWD = -100  # renameat2(2): paths relative to the working folder
_RENAME_EXCHANGE = 2  # renameat2(2): swap both paths in one step


def _make_parent(path: Path) -> None:
    """Create ``path``'s folder; InputError naming ``path`` when that is impossible."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{path}: cannot create its folder ({exc.strerror})") from None


@contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """A temporary path beside ``path`` (same suffix) to write to.

    On success it is renamed over ``path``, so readers never see a half-written file; on an
    exception it is removed and ``path`` is left as it was. InputError when ``path`` is a
    folder or lies under a file.
    """
    check_output_file(path)
    _make_parent(path)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        yield tmp
        os.chmod(tmp, FILE_MODE)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _exchange(a: Path, b: Path) -> bool:
    """Swap two existing paths in one step (Linux renameat2); False where unsupported."""
    if not sys.platform.startswith("linux"):
        return False
    rename = getattr(ctypes.CDLL(None, use_errno=True), "renameat2", None)
    if rename is None:
        return False
    return rename(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0


def _link_or_copy(source: str, target: str) -> None:
    """Hard-link ``source`` as ``target`` (no data copied); copy where links are refused."""
    try:
        os.link(source, target)
    except OSError:
        shutil.copy2(source, target)


def _carry_over(old: Path, new: Path, carry: Callable[[Path], bool]) -> None:
    """Hard-link (or copy) the files of ``old`` that ``carry`` accepts into ``new``."""
    for entry in old.iterdir():
        if entry.is_file() and carry(entry) and not (new / entry.name).exists():
            _link_or_copy(str(entry), str(new / entry.name))


def _remove_leftovers(path: Path) -> None:
    """Delete the hidden temporary folders a killed ``atomic_folder(path)`` left beside it
    (``.NAME.XXXXXXXX`` and ``.NAME.old.XXXXXXXX``, as ``tempfile.mkdtemp`` names them; a
    folder of another name, or of another output's, is never matched)."""
    pattern = re.compile(rf"\.{re.escape(path.name)}\.(old\.)?[a-z0-9_]{{8}}")
    for entry in path.parent.iterdir():
        if pattern.fullmatch(entry.name) and entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry, ignore_errors=True)


@contextmanager
def atomic_folder(path: Path, carry: Callable[[Path], bool] | None = None) -> Iterator[Path]:
    """A temporary folder beside ``path`` to fill; on success it replaces ``path``.

    Files (not folders) of the old folder that ``carry`` accepts are taken along (hard
    links), unless the new folder has one of that name. The swap is one step where the system
    offers it (Linux); elsewhere the old folder is moved aside and removed after the new one
    is in place. On an exception the temporary folder is removed and ``path`` is left as it
    was. A kill leaves at most a hidden temporary folder beside ``path``, which the next
    write of ``path`` removes.
    """
    path = check_output_folder(Path(path)).absolute()
    _make_parent(path)
    _remove_leftovers(path)
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
    try:
        yield tmp
        os.chmod(tmp, FOLDER_MODE)
        if not path.exists():
            os.rename(tmp, path)
            return
        if carry is not None:
            _carry_over(path, tmp, carry)
        if not _exchange(tmp, path):
            aside = Path(tempfile.mkdtemp(prefix=f".{path.name}.old.", dir=path.parent))
            aside.rmdir()  # a free name beside the folder
            os.rename(path, aside)
            os.rename(tmp, path)
            tmp = aside
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
