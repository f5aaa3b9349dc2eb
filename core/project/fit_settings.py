"""How the app fits an animal: the user's choices per animal and the FitConfig they make.

Quality presets scale the optimisation steps of the engine's defaults; the frame range and
rate, refraction and the native-resolution crops map onto FitConfig's own fields.
"""

import hashlib
from dataclasses import dataclass, replace
from datetime import datetime
from pathlib import Path

from dolphinfit.core.fit.config import FitConfig

# Preset → multiplier of every stage's steps. "standard" is the engine's defaults (measured by
# `dolphinfit bench fit`); "quick" is for a first look, "thorough" for the final figures.
QUALITY_STEP_SCALE = {"quick": 0.5, "standard": 1.0, "thorough": 2.0}
FITS_SUFFIX = ".fits"  # beside PROJECT.dolphinfit: PROJECT.fits/<clip>_<animal>/


@dataclass(frozen=True)
class FitSettings:
    """``start_s``/``end_s``: the part of the clip to fit (None: from the start / to the end);
    ``fps``: frames fitted per second of video; ``quality``: a QUALITY_STEP_SCALE key."""

    start_s: float | None = None
    end_s: float | None = None
    fps: float = FitConfig().fps
    quality: str = "standard"
    refraction: bool = FitConfig().use_refraction
    roi: bool = FitConfig().use_roi

    def __post_init__(self) -> None:
        if self.quality not in QUALITY_STEP_SCALE:
            raise ValueError(f"quality must be one of {', '.join(QUALITY_STEP_SCALE)}, "
                             f"got {self.quality!r}")
        if not (self.fps > 0):
            raise ValueError(f"frames per second to fit must be positive, got {self.fps!r}")
        if None not in (self.start_s, self.end_s) and self.end_s <= self.start_s:
            raise ValueError(f"the fit's end ({self.end_s} s) must come after its start "
                             f"({self.start_s} s)")
        if any(t is not None and t < 0 for t in (self.start_s, self.end_s)):
            raise ValueError("the fit's start and end are seconds from the clip's start (≥ 0)")


def fit_config(settings: FitSettings, base: FitConfig = FitConfig()) -> FitConfig:
    """The engine configuration for ``settings``."""
    scale = QUALITY_STEP_SCALE[settings.quality]

    def steps(n: int) -> int:
        return max(1, round(n * scale))

    return replace(base, steps_global=steps(base.steps_global),
                   steps_body=steps(base.steps_body), steps_shape=steps(base.steps_shape),
                   heading_trial_steps=steps(base.heading_trial_steps),
                   coarse_steps=round(base.coarse_steps * scale),
                   shape_full_steps=round(base.shape_full_steps * scale), fps=settings.fps,
                   start_s=settings.start_s, end_s=settings.end_s,
                   use_refraction=settings.refraction, use_roi=settings.roi)


def clip_key(clip_media: str | Path) -> str:
    """A file-name-safe key of a clip: its stem and a short hash of its path in the project
    (DJI names repeat from card to card: DJI_0001.MP4 of two days must not share files)."""
    digest = hashlib.sha1(Path(clip_media).as_posix().encode("utf-8")).hexdigest()[:6]
    return f"{Path(clip_media).stem}-{digest}"


def _animal_name(clip_media: str, animal_id: str) -> str:
    return f"{clip_key(clip_media)}_{animal_id}".replace(" ", "-").replace("/", "-")


def fit_dir(project_path: Path, clip_media: str, animal_id: str) -> Path:
    """Where an animal's fit is kept: ``PROJECT.fits/<clip key>_<animal id>/``."""
    return (project_path.with_name(project_path.stem + FITS_SUFFIX)
            / _animal_name(clip_media, animal_id))


def hw_table_path(project_path: Path, clip_media: str, animal_id: str) -> Path:
    """Where HW ratios taken from an animal's fit are kept, a new table each time (the
    results' table cache and undo both rely on a table never changing under its name):
    ``PROJECT.fits/<clip key>_<animal id>_hw_<time>.csv``."""
    stamp = datetime.now().strftime("%Y%m%d-%H%M%S-%f")
    return (project_path.with_name(project_path.stem + FITS_SUFFIX)
            / f"{_animal_name(clip_media, animal_id)}_hw_{stamp}.csv")
