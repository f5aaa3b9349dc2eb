"""A task's folder appears whole or not at all: the task writes into a hidden partial folder
beside it and renames that into place once everything, its record last, is written. A kill at
any moment leaves the old complete folder (or none) and at most a leftover that the task's
next run removes."""

import glob
import shutil
import uuid
from pathlib import Path

PARTIAL_SUFFIX = ".partial"
OLD_SUFFIX = ".old"


def partial_folder(out_dir: Path, name: str) -> Path:
    """A new, empty hidden folder to write task ``name``'s outputs into."""
    folder = out_dir / f".{name}.{uuid.uuid4().hex[:8]}{PARTIAL_SUFFIX}"
    folder.mkdir(parents=True)
    return folder


def remove_leftovers(out_dir: Path, name: str) -> None:
    """Delete partial and replaced folders of task ``name`` left by a killed run."""
    pattern = f".{glob.escape(name)}.{'[0-9a-f]' * 8}"
    for suffix in (PARTIAL_SUFFIX, OLD_SUFFIX):
        for leftover in out_dir.glob(pattern + suffix):
            shutil.rmtree(leftover, ignore_errors=True)


def install_folder(partial: Path, final: Path) -> None:
    """Put the finished ``partial`` folder in the place of ``final`` (replacing an older one,
    which stays whole until the new one is in place)."""
    if final.exists():
        old = partial.with_name(partial.name.removesuffix(PARTIAL_SUFFIX) + OLD_SUFFIX)
        final.rename(old)
        partial.rename(final)
        shutil.rmtree(old, ignore_errors=True)
    else:
        partial.rename(final)
