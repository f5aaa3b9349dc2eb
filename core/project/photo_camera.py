"""A still photo's own camera, from its EXIF: the real focal length and the size of a pixel.

Metres per pixel need the focal length in pixels, focal mm / pixel mm, and a crop keeps
both. The pixel size comes from the EXIF focal-plane tags where the camera writes them,
else from resources/camera_sensors.json: per camera model (EXIF Model), its sensor width
and the image width it writes at full size, with the source of each entry; pixel = sensor /
native width (SONY ILCE-5100: 23.5 mm / 6000 px = 3.9167 µm). The camera is stored as a
CameraPreset whose sensor width is that pixel size times the photo's own width. A resized
photo (not a crop) has other pixels: its camera is the user's to set.

Such a camera is approximate (CameraPreset): the focal length is the lens's nominal one and
the sensor width the maker's.

Schema of camera_sensors.json::

    {"schema_version": 1, "sensors": [{"make": "SONY", "model": "ILCE-5100",
      "sensor_width_mm": 23.5, "native_width_px": 6000, "source": …}, …]}
"""

from dataclasses import dataclass
from pathlib import Path

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.exif import ExifCamera, read_exif_camera
from dolphinfit.core.io.json_file import check_schema_version, dataclass_from_json, read_json
from dolphinfit.core.limits import IMAGE_SIZE_PX, SENSOR_WIDTH_MM, in_range
from dolphinfit.core.resources import resource_path

SENSORS_FILE = "camera_sensors.json"
SENSORS_SCHEMA_VERSION = 1
UM_PER_MM = 1000.0


@dataclass(frozen=True)
class SensorEntry:
    """A camera model's sensor width and the width of its full-size images, with a source."""

    make: str
    model: str
    sensor_width_mm: float
    native_width_px: int
    source: str

    @property
    def pixel_mm(self) -> float:
        """The sensor's pixel size (mm)."""
        return self.sensor_width_mm / self.native_width_px


def load_sensor_table(path: Path | None = None) -> dict[str, SensorEntry]:
    """The sensor table (the bundled one by default) by lower-case model (makers write their
    Make differently: a Mavic 2 Pro's photos say "Hasselblad"); InputError naming the file
    and entry when it is malformed or a value implausible."""
    path = resource_path(SENSORS_FILE) if path is None else path
    data = read_json(path, "the camera sensor table")
    check_schema_version(data, SENSORS_SCHEMA_VERSION, str(path))
    if not isinstance(data.get("sensors"), list):
        raise InputError(f"{path}: 'sensors' must be a list")
    table = {}
    for index, item in enumerate(data["sensors"]):
        where = f"{path}: sensor #{index}"
        entry = dataclass_from_json(SensorEntry, item, where)
        in_range(entry.sensor_width_mm, SENSOR_WIDTH_MM, f"{where}: sensor_width_mm")
        in_range(entry.native_width_px, IMAGE_SIZE_PX, f"{where}: native_width_px")
        table[entry.model.lower()] = entry
    return table


def _pixel_size(exif: ExifCamera, width_px: int,
                table: dict[str, SensorEntry]) -> tuple[float | None, str]:
    """The photo's pixel size (mm) and where it came from; None and why where unknown."""
    if exif.pixel_mm is not None:
        return exif.pixel_mm, "the EXIF focal-plane resolution"
    entry = table.get(exif.model.lower())
    if entry is None:
        return None, f"{exif.name} is not in the sensor table and its EXIF gives no pixel size"
    if width_px > entry.native_width_px:
        return None, (f"the photo is {width_px} px wide, wider than the {entry.native_width_px} "
                      f"px {exif.name} writes: resized, so its pixel size is unknown")
    return entry.pixel_mm, (f"{entry.sensor_width_mm:g} mm / {entry.native_width_px} px "
                            f"({entry.source})")


def photo_camera(path: Path, width_px: int, height_px: int,
                 table: dict[str, SensorEntry] | None = None) -> tuple[
                     CameraPreset | None, str]:
    """The camera of the still at ``path`` (``width_px`` × ``height_px``) from its EXIF, and
    what the user is told; None and why where the EXIF gives no focal length or no pixel size
    can be found (module doc). Reads the file (run it off the GUI thread)."""
    try:
        exif = read_exif_camera(path)
        table = load_sensor_table() if table is None else table
    except InputError as exc:
        return None, str(exc)
    if exif is None:
        return None, f"{path.name} has no EXIF naming its camera"
    if exif.focal_mm is None:
        return None, f"{path.name}'s EXIF ({exif.name}) gives no focal length"
    pixel_mm, pixel_source = _pixel_size(exif, width_px, table)
    if pixel_mm is None:
        return None, pixel_source
    description = (f"from the photo's EXIF: {exif.name}, {exif.focal_mm:g} mm, "
                   f"pixel {pixel_mm * UM_PER_MM:.2f} µm")
    camera = CameraPreset(
        name=exif.name, description=description, focal_mm=exif.focal_mm,
        sensor_width_mm=pixel_mm * width_px, image_width_px=width_px, image_height_px=height_px,
        source=f"EXIF of {path.name}; pixel size from {pixel_source}", approximate=True)
    return camera, description
