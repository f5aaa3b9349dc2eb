"""The model-based fit of one animal in a worker (ui/workers/job_worker.py): its own reader of the
clip, the clip's masks and altitude, the engine configuration of the animal's fit settings and
the project's HW table; the outputs are written into
the animal's fit folder, replacing an older fit only once the new one is complete on disk
(``core.fit.outputs.write_outputs`` writes the folder atomically).
``finished`` carries (FitResult, fit folder); a cancelled or diverged fit is a result too,
with its status and the best state it reached."""

import threading
from dataclasses import dataclass
from pathlib import Path

from dolphinfit.core.camera_presets import CameraPreset, preset_resolution_mismatch
from dolphinfit.core.device import DEFAULT_DEVICE
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.io.media import open_media
from dolphinfit.core.io.telemetry import Telemetry
from dolphinfit.core.measure.lens import LensModel
from dolphinfit.core.progress import Cancelled, ProgressCallback
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.ui.workers.job_worker import DEVICE_SETTING, JobWorker


@dataclass(frozen=True, eq=False)
class FitJob:
    """Everything one fit needs, read on the GUI thread before it starts."""

    discard: threading.Event  # set: the app is closing, a result is not written
    media: Path
    telemetry: Telemetry
    masks: Path
    camera: CameraPreset
    out_dir: Path
    config: FitConfig    # the animal's fit settings and the project's HW table
    lens: LensModel | None = None   # the clip's: frames and masks undistorted for the fit
    device: str = DEFAULT_DEVICE    # where the fit computes (core.device), resolved in the job


def run_fit_job(job: FitJob, progress: ProgressCallback, cancel: threading.Event) -> tuple:
    """Fit, write the outputs, return (FitResult, fit folder). Loads torch: worker only."""
    from dolphinfit.core.device import resolve_device
    from dolphinfit.core.fit.outputs import write_outputs
    from dolphinfit.core.fit.pipeline import fit_clip
    from dolphinfit.core.model.template import load_template
    from dolphinfit.core.runtime import configure_threads

    configure_threads()
    device = resolve_device(job.device, DEVICE_SETTING)
    with open_media(job.media) as frames:
        mismatch = preset_resolution_mismatch(job.camera, frames.clip.width_px,
                                              frames.clip.height_px)
        if mismatch:
            raise InputError(f"camera: {mismatch}; fix it in Clip → Camera… before fitting")
        masks = read_masks(job.masks, frames.clip)
        run = fit_clip(frames, job.telemetry, masks, job.camera.intrinsics(),
                       job.config, progress=progress, cancel=cancel, lens=job.lens,
                       device=device)
    if job.discard.is_set():
        raise Cancelled()  # closing: an older complete fit is not replaced by a partial one
    write_outputs(run.result, run.data, load_template(), job.out_dir)
    return run.result, job.out_dir


class FitWorker(JobWorker):
    """One fit at a time, off the GUI thread."""

    def start(self, job: FitJob) -> bool:
        """Fit in the background; False if a fit is already running."""
        return self.run_job(lambda progress, cancel: run_fit_job(job, progress, cancel))
