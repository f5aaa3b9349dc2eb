"""Lens models kept with camera presets. `dolphinfit camera lens PRESET LENS.json` (or
`dolphinfit calibrate lens … --preset PRESET`) stores a lens calibrated for a preset's video
mode as ``lenses/PRESET.json`` in the user's config folder, beside ``cameras.json``; a
measurement or fit made with that preset then goes through it unless another lens is given,
and the app gives it to a clip whose camera is set to the preset. None ships with dolphinfit:
no lens was measured for this project.
"""

import re
from pathlib import Path

from dolphinfit.core.camera_presets import CameraPreset, config_dir
from dolphinfit.core.measure.lens import LensModel, read_lens, write_lens

LENS_FOLDER = "lenses"


def preset_lens_path(preset_name: str) -> Path:
    """Where the lens of the preset called ``preset_name`` is kept."""
    return config_dir() / LENS_FOLDER / f"{re.sub(r'[^A-Za-z0-9._-]', '_', preset_name)}.json"


def preset_lens(preset_name: str | None) -> LensModel | None:
    """The lens stored for the preset (None: no preset, or none stored); InputError naming
    the file when it cannot be read."""
    if preset_name is None:
        return None
    path = preset_lens_path(preset_name)
    return read_lens(path) if path.exists() else None


def store_preset_lens(preset: CameraPreset, lens: LensModel) -> Path:
    """Keep ``lens`` for ``preset``; InputError when it was calibrated on another image
    size than the preset's video mode."""
    lens.check_image_size(preset.image_width_px, preset.image_height_px,
                          f"camera preset {preset.name!r}")
    path = preset_lens_path(preset.name)
    write_lens(lens, path)
    return path
