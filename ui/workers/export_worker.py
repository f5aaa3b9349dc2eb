"""Exports of measured frames in a worker: every frame measured with the Monte Carlo
(core.project.evaluate), then written with its receipt (core.project.exports), as one job with
progress ("measure", then "write") and cancel. ``finished`` carries (paths written, frames left
out and why)."""

import threading
from collections.abc import Sequence
from pathlib import Path

from PySide6.QtCore import QObject

from dolphinfit.core.measure.uncertainty import DEFAULT_NUM_DRAWS
from dolphinfit.core.progress import ProgressCallback, part_of
from dolphinfit.core.project.evaluate import frame_results
from dolphinfit.core.project.exports import MediaFrames, export_frames
from dolphinfit.core.project.model import MeasurementKey, Project
from dolphinfit.ui.workers.job_worker import JobWorker


class ExportWorker(JobWorker):
    """One export at a time, off the GUI thread."""

    def __init__(self, parent: QObject | None = None,
                 num_draws: int = DEFAULT_NUM_DRAWS) -> None:
        super().__init__(parent)
        self.num_draws = num_draws

    def start(self, project: Project, project_path: Path, keys: Sequence[MeasurementKey],
              out_dir: Path, stem: str, receipts: bool = True) -> bool:
        """Export the frames ``keys`` of the project saved at ``project_path`` (media and
        altitude files are relative to it) as ``out_dir/STEM_*``; receipts need the media."""
        keys, num_draws = list(keys), self.num_draws

        def job(progress: ProgressCallback, cancel: threading.Event) -> tuple[list, list]:
            total = 2 * len(keys)  # measuring each frame, then writing each measured one
            results, skipped = frame_results(project, Path(project_path), keys, num_draws,
                                             part_of(progress, 0, total), cancel)
            with MediaFrames(project, Path(project_path)) as frames:
                paths = export_frames(project, results, Path(out_dir), stem,
                                      frames if receipts else None,
                                      part_of(progress, total - len(results), total), cancel,
                                      Path(project_path).parent)
            return paths, skipped + frames.notes

        return self.run_job(job)
