"""The body without its fins, as the clip's camera saw it: inside the clip's true mask, clear
of its fluke lobes, and most of the animal."""

import numpy as np

from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.synth.body_view import body_mask
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import read_part_masks
from dolphinfit.core.synth.sample import ensure_clip

CONFIG = SynthConfig(seed=3, width_px=480, height_px=270, fps=5.0, duration_s=0.4,
                     altitude_m=6.0, heading_deg=10.0, sea_state=0.0)


def test_the_body_is_the_true_mask_less_its_fins(tmp_path):
    files = ensure_clip(CONFIG, tmp_path / "clip")
    whole = read_masks(files.masks_dir).mask(1)
    flukes = read_part_masks(files.parts)["flukes"][1]
    body = body_mask(CONFIG, 1)
    assert body.shape == whole.shape
    assert np.count_nonzero(body & ~whole) <= 0.01 * np.count_nonzero(body)
    assert np.count_nonzero(body & flukes) <= 0.05 * np.count_nonzero(flukes)
    assert 0.6 < np.count_nonzero(body) / np.count_nonzero(whole) < 0.8   # fins: about 0.3
