"""Whether a project's media are still the files it measured: each clip's media against the
fingerprint taken when it was added (core/io/media_fingerprint.py), and the clips re-stamped
once the user accepts the files as they are now."""

from dataclasses import replace
from pathlib import Path

from dolphinfit.core.io.media_fingerprint import media_fingerprint, same_media
from dolphinfit.core.project.model import Project
from dolphinfit.core.project.project_file import media_path


def changed_media(project: Project, project_path: Path) -> list[int]:
    """The clips whose media exist but hold other content than when they were added (clips
    without a fingerprint, or whose media are missing or unreadable, are not listed)."""
    changed = []
    for idx, clip in enumerate(project.clips):
        path = media_path(project_path, clip)
        if clip.media_fingerprint is None or not path.exists():
            continue
        try:
            if not same_media(clip.media_fingerprint, path):
                changed.append(idx)
        except OSError:
            continue
    return changed


def with_media_accepted(project: Project, project_path: Path, clips: list[int]) -> Project:
    """``project`` with the fingerprints of ``clips`` taken again from their media now."""
    entries = list(project.clips)
    for idx in clips:
        entries[idx] = replace(entries[idx], media_fingerprint=media_fingerprint(
            media_path(project_path, entries[idx])))
    return replace(project, clips=tuple(entries))
