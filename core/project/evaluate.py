"""Results of many measured frames at once (exports of an animal or a whole project): each
clip's media is opened once for its frame timing, its altitude aligned and its SRT's clock
read, then every frame is measured with the Monte Carlo and dated."""

import threading
from collections.abc import Sequence
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.media import open_media
from dolphinfit.core.model.hw_spec import resolve_hw
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel
from dolphinfit.core.project.model import MeasurementKey, Project, get_measurement
from dolphinfit.core.project.project_file import media_path
from dolphinfit.core.project.results import (
    FrameResult, clip_clock_start, clip_telemetry, frame_altitude, frame_recorded_at,
    measure_frame, project_hw_spec,
)


def frame_results(project: Project, project_path: Path, keys: Sequence[MeasurementKey],
                  num_draws: int, progress: ProgressCallback | None = None,
                  cancel: threading.Event | None = None) -> tuple[list[FrameResult], list[str]]:
    """The results of ``keys`` and, for the frames that could not be measured, why."""
    hw = resolve_hw(project_hw_spec(project, project_path.parent))
    results, skipped = [], []
    telemetry, clock_start = {}, {}
    for done, key in enumerate(keys):
        check_cancel(cancel)
        clip = project.clips[key.clip]
        frame_idx = get_measurement(project, key).frame_idx
        where = f"{clip.name} frame {frame_idx}"
        try:
            if key.clip not in telemetry:
                with open_media(media_path(project_path, clip)) as source:
                    telemetry[key.clip] = clip_telemetry(project_path.parent, clip, source.clip)
                clock_start[key.clip] = clip_clock_start(project_path.parent, clip, source.clip)
            altitude = frame_altitude(telemetry[key.clip], frame_idx)
            recorded_at = frame_recorded_at(clock_start[key.clip], telemetry[key.clip], frame_idx)
            results.append(measure_frame(project, key, altitude, clip.altitude.source, hw,
                                         num_draws, recorded_at=recorded_at))
        except (InputError, ValueError) as exc:
            skipped.append(f"{where}: {exc}")
        if progress is not None:
            progress(Progress("measure", done + 1, len(keys), where))
    return results, skipped


def all_keys(project: Project, clip: int | None = None,
             animal: int | None = None) -> list[MeasurementKey]:
    """Keys of every measured frame of the project, of one clip, or of one animal."""
    return [MeasurementKey(c, a, m)
            for c, clip_entry in enumerate(project.clips) if clip in (None, c)
            for a, animal_entry in enumerate(clip_entry.animals) if animal in (None, a)
            for m in range(len(animal_entry.measurements))]
