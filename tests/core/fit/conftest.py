"""The fit tests' synthetic clip, rendered once for every module here, and a tiny fit of it,
made once for every module here too."""

from dataclasses import replace

import pytest

from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.pipeline import fit_clip
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.io.masks import read_png_folder
from dolphinfit.core.io.telemetry import load_telemetry
from dolphinfit.core.io.video import VideoReader
from dolphinfit.core.synth.clip import make_clip
from dolphinfit.core.synth.config import Effects, SynthConfig

# A 2.3 m animal in 1920×1080 footage at 20 m (1.46 cm per pixel), 8 frames.
# Part shapes vary little (SD 0.02), so the test measures the pipeline, not how much height a
# top view cannot see.
CLIP = SynthConfig(seed=21, width_px=1920, height_px=1080, fps=5.0, duration_s=1.6,
                   altitude_m=20.0, length_m=2.3, shape_sd=0.02, heading_deg=-20.0,
                   speed_m_s=0.8, dive_depth_m=0.0,
                   effects=Effects(profile_warp=False, scattering=False, ripples=False,
                                   glints=False, compression=False))
QUICK = FitConfig(heading_trial_steps=8, steps_global=20, steps_body=20, steps_shape=40,
                  hw_table=None)
TINY = replace(QUICK, heading_trial_steps=2, steps_global=3, steps_body=2, steps_shape=3)
INTRINSICS = CameraIntrinsics.from_sensor(12.29, 17.27, 1920, 1080)


@pytest.fixture(scope="session")
def clip_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("fitclip")
    make_clip(CLIP, out)
    return out


def fit_on_clip(clip_dir, config, progress=None, cancel=None, device="cpu"):
    """fit_clip on the open clip, as the GUI worker calls it."""
    with VideoReader(clip_dir / "clip.mkv") as frames:
        masks = read_png_folder(clip_dir / "masks", frames.clip)
        telemetry = load_telemetry(frames.clip, clip_dir / "altitude.csv")
        return fit_clip(frames, telemetry, masks, INTRINSICS, config, progress, cancel,
                        device=device)


@pytest.fixture(scope="session")
def tiny_run(clip_dir):
    """A tiny fit (TINY, all 8 frames) through fit_clip with every progress report recorded;
    read only: the modules here share it."""
    reports = []
    return fit_on_clip(clip_dir, TINY, progress=reports.append), reports
