"""Stills with the EXIF a camera writes: maker, model, focal length and focal-plane
resolution, for tests that open photos."""

from pathlib import Path

import numpy as np
from PIL import Image

from dolphinfit.core.io.exif import (
    IFD_EXIF, TAG_FOCAL_LENGTH, TAG_FOCAL_PLANE_RESOLUTION_UNIT, TAG_FOCAL_PLANE_X_RESOLUTION,
    TAG_MAKE, TAG_MODEL,
)

UNIT_CM = 3  # FocalPlaneResolutionUnit: centimetre
MM_PER_CM = 10.0


def write_still(path: Path, rgb: np.ndarray, focal_mm: float | None = None,
                pixel_mm: float | None = None, make: str = "DJI",
                model: str = "TEST-CAM") -> Path:
    """``rgb`` (H, W, 3) uint8 saved at ``path`` (format by suffix) with EXIF naming
    ``make`` ``model``, its ``focal_mm`` and, as focal-plane pixels per cm, ``pixel_mm``
    (each left out where None)."""
    exif = Image.Exif()
    exif[TAG_MAKE], exif[TAG_MODEL] = make, model
    exif_ifd = exif.get_ifd(IFD_EXIF)
    if focal_mm is not None:
        exif_ifd[TAG_FOCAL_LENGTH] = focal_mm
    if pixel_mm is not None:
        exif_ifd[TAG_FOCAL_PLANE_X_RESOLUTION] = MM_PER_CM / pixel_mm
        exif_ifd[TAG_FOCAL_PLANE_RESOLUTION_UNIT] = UNIT_CM
    Image.fromarray(rgb).save(path, exif=exif)
    return path
