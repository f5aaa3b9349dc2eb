"""The fit tests' synthetic clip, rendered once for every module here."""

import pytest

from core.synth.clip import make_clip
from core.synth.config import Effects, SynthConfig

# A 2.3 m animal in 1920×1080 footage at 20 m (1.46 cm per pixel), 8 frames.
# Part shapes vary little (SD 0.02), so the test measures the pipeline, not how much height a
# top view cannot see.
CLIP = SynthConfig(seed=21, width_px=1920, height_px=1080, fps=5.0, duration_s=1.6,
                   altitude_m=20.0, length_m=2.3, shape_sd=0.02, heading_deg=-20.0,
                   speed_m_s=0.8, dive_depth_m=0.0,
                   effects=Effects(profile_warp=False, scattering=False, ripples=False,
                                   glints=False, compression=False))


@pytest.fixture(scope="session")
def clip_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("fitclip")
    make_clip(CLIP, out)
    return out
