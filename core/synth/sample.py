"""The bundled sample clip for the demo and the GUI, made on first use and cached.

It is not stored in the repository: ``ensure_sample`` renders it deterministically from
``SAMPLE_CONFIG`` into the user's cache (``$DOLPHINFIT_CACHE_DIR``, else
``$XDG_CACHE_HOME/dolphinfit``, else ``~/.cache/dolphinfit``) and reuses it while its
``truth.json`` records the same configuration.
"""

import os
from pathlib import Path

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET
from dolphinfit.core.progress import ProgressCallback
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import ClipFiles, clip_files, made_from

CACHE_DIR_ENV = "DOLPHINFIT_CACHE_DIR"
SAMPLE_NAME = "sample-v2"
# the animal's heights follow the default HW table, as the fit assumes by default (v1 had the
# template's heights)
SAMPLE_CONFIG = SynthConfig(seed=7, width_px=1280, height_px=720, fps=10.0, duration_s=5.0,
                            altitude_m=18.0, length_m=2.45, heading_deg=20.0, sea_state=0.35,
                            dive_depth_m=0.5, hw_table=DEFAULT_PRESET)


def cache_dir() -> Path:
    """Where generated data is cached."""
    if os.environ.get(CACHE_DIR_ENV):
        return Path(os.environ[CACHE_DIR_ENV])
    xdg = os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache")
    return Path(xdg) / "dolphinfit"


def ensure_clip(config: SynthConfig, out_dir: Path,
                progress: ProgressCallback | None = None) -> ClipFiles:
    """The files of the clip of ``config`` in ``out_dir``, rendered first if they are missing
    or were made from another configuration (only rendering loads the model stack, torch)."""
    files = clip_files(out_dir, config)
    if made_from(files, config):
        return files
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:  # a file where a folder should be, no permission, a full disk
        raise InputError(f"{out_dir}: the cache folder cannot be made ({exc.strerror or exc}); "
                         f"set {CACHE_DIR_ENV} to a folder you can write") from None
    from dolphinfit.core.synth.clip import make_clip
    return make_clip(config, out_dir, progress=progress)


def ensure_sample(progress: ProgressCallback | None = None) -> ClipFiles:
    """The sample clip's files, rendering them first if they are missing or stale."""
    return ensure_clip(SAMPLE_CONFIG, cache_dir() / SAMPLE_NAME, progress)
