"""The clip being viewed: its opened media and its altitude per frame."""

from dataclasses import dataclass
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.media import FrameSource, open_media
from dolphinfit.core.io.telemetry import Telemetry
from dolphinfit.core.project.model import AltitudeSpec, ClipEntry
from dolphinfit.core.project.project_file import media_path
from dolphinfit.core.project.results import clip_telemetry


@dataclass
class ClipSession:
    """Media and telemetry of one clip: ``altitude`` is the spec the telemetry was read from;
    ``telemetry_error`` says why there is no altitude."""

    clip_idx: int
    source: FrameSource
    altitude: AltitudeSpec | None
    telemetry: Telemetry | None
    telemetry_error: str | None = None

    def close(self) -> None:
        self.source.close()


def read_session_telemetry(project_path: Path, clip: ClipEntry, clip_idx: int,
                           source: FrameSource) -> ClipSession:
    """A session of opened media with the clip's altitude read (run in a background job)."""
    try:
        telemetry = clip_telemetry(project_path.parent, clip, source.clip)
        error = None if telemetry is not None else "no altitude yet: Clip → Altitude…"
    except InputError as exc:
        telemetry, error = None, str(exc)
    return ClipSession(clip_idx, source, clip.altitude, telemetry, error)


def open_session(project_path: Path, clip: ClipEntry, clip_idx: int) -> ClipSession:
    """Open a clip's media and read its altitude (run in a background job)."""
    source = open_media(media_path(project_path, clip))
    return read_session_telemetry(project_path, clip, clip_idx, source)
