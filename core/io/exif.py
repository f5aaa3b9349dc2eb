"""The camera a still photo's EXIF names: maker, model, real focal length and, where the
camera writes its focal-plane resolution, the size of a pixel on the sensor.

EXIF 2.3 tags read: Make (0x010F) and Model (0x0110) in IFD0; FocalLength (0x920A),
FocalPlaneXResolution (0xA20E) and FocalPlaneResolutionUnit (0xA210) in the Exif IFD. The
focal length is the lens's own (not FocalLengthIn35mmFilm). Files Pillow cannot read, and
photos without EXIF, name no camera.
"""

import math
from dataclasses import dataclass
from pathlib import Path

from PIL import Image, UnidentifiedImageError

from dolphinfit.core.limits import FOCAL_MM, PIXEL_DIMENSION_MM, in_range

TAG_MAKE = 0x010F
TAG_MODEL = 0x0110
IFD_EXIF = 0x8769
TAG_FOCAL_LENGTH = 0x920A
TAG_FOCAL_PLANE_X_RESOLUTION = 0xA20E
TAG_FOCAL_PLANE_RESOLUTION_UNIT = 0xA210
# FocalPlaneResolutionUnit (EXIF 2.3 §4.6.5): 2 inch, 3 centimetre; 1 (none) gives no size
MM_PER_RESOLUTION_UNIT = {2: 25.4, 3: 10.0}


@dataclass(frozen=True)
class ExifCamera:
    """The camera of a photo: ``make`` and ``model`` as written (trimmed); ``focal_mm``: the
    lens's real focal length, None where absent or 0 (manual lenses write 0); ``pixel_mm``:
    the sensor's pixel size from the focal-plane tags, None where they are absent."""

    make: str
    model: str
    focal_mm: float | None
    pixel_mm: float | None

    @property
    def name(self) -> str:
        """"SONY ILCE-5100": the maker, then the model unless it starts with the maker."""
        if self.model.lower().startswith(self.make.lower()):
            return self.model
        return f"{self.make} {self.model}".strip()


def _text(value: object) -> str:
    """An EXIF ASCII value without the NULs and spaces some cameras pad it with."""
    if isinstance(value, bytes):
        value = value.decode("ascii", "replace")
    return str(value or "").strip("\x00 ").strip()


def _number(value: object) -> float | None:
    """An EXIF rational as a float; None where absent, not a finite number or 0/0."""
    try:
        number = float(value)
    except (TypeError, ValueError, ZeroDivisionError):
        return None
    return number if math.isfinite(number) else None


def _pixel_mm(exif_ifd: dict, where: str) -> float | None:
    """The pixel size (mm) of the focal-plane tags; None where absent or of no unit."""
    per_unit = _number(exif_ifd.get(TAG_FOCAL_PLANE_X_RESOLUTION))
    unit_mm = MM_PER_RESOLUTION_UNIT.get(exif_ifd.get(TAG_FOCAL_PLANE_RESOLUTION_UNIT))
    if per_unit is None or per_unit <= 0 or unit_mm is None:
        return None
    return in_range(unit_mm / per_unit, PIXEL_DIMENSION_MM, f"{where}: FocalPlaneXResolution")


def read_exif_camera(path: Path) -> ExifCamera | None:
    """The camera ``path``'s EXIF names; None without EXIF, Make or Model. InputError naming
    the file and tag when a focal length or pixel size is implausible (core.limits)."""
    try:
        with Image.open(path) as image:
            exif = image.getexif()
            exif_ifd = dict(exif.get_ifd(IFD_EXIF))
    except (OSError, UnidentifiedImageError, ValueError, SyntaxError):
        return None
    make, model = _text(exif.get(TAG_MAKE)), _text(exif.get(TAG_MODEL))
    if not make or not model:
        return None
    focal_mm = _number(exif_ifd.get(TAG_FOCAL_LENGTH))
    if focal_mm is not None and focal_mm > 0:
        focal_mm = in_range(focal_mm, FOCAL_MM, f"{path}: EXIF FocalLength")
    else:
        focal_mm = None
    return ExifCamera(make, model, focal_mm, _pixel_mm(exif_ifd, str(path)))
