"""Whether a project's media are still the files it measured: each clip's media against the
fingerprint taken when it was added (core/io/media_fingerprint.py), and the clips stamped
with the files' fingerprints now once the user accepts them as they are."""

from dataclasses import replace
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.media_fingerprint import changed_fingerprint
from dolphinfit.core.project.model import Project
from dolphinfit.core.project.project_file import media_path


def changed_media(project: Project, project_path: Path) -> dict[int, str]:
    """The clips whose media exist but hold other content than when they were added, each
    with its media's fingerprint now (clips without a fingerprint, or whose media are missing
    or unreadable, are not listed)."""
    changed = {}
    for idx, clip in enumerate(project.clips):
        path = media_path(project_path, clip)
        if clip.media_fingerprint is None or not path.exists():
            continue
        try:
            now = changed_fingerprint(clip.media_fingerprint, path)
        except (OSError, InputError):   # unreadable, or a folder left without frames
            continue
        if now is not None:
            changed[idx] = now
    return changed


def with_media_accepted(project: Project, changed: dict[int, str]) -> Project:
    """``project`` with the clips of ``changed`` stamped with their media's fingerprints now."""
    clips = list(project.clips)
    for idx, fingerprint in changed.items():
        clips[idx] = replace(clips[idx], media_fingerprint=fingerprint)
    return replace(project, clips=tuple(clips))
