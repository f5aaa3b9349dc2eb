"""Named drone cameras and video modes (presets): the bundled table and the user's own.

Bundled presets are in resources/cameras.json; the user's are saved to ``cameras.json`` in
:func:`config_dir` and override bundled presets of the same name. Both files share one schema::

    {"schema_version": 1, "presets": [{"name": …, "description": …, "focal_mm": …,
      "sensor_width_mm": …, "image_width_px": …, "image_height_px": …, "source": …,
      "approximate": …}, …]}
"""

import os
import re
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from dolphinfit.core.errors import InputError
from dolphinfit.core.intrinsics import CameraIntrinsics, require_positive
from dolphinfit.core.io.calibration_table import CalibrationTable
from dolphinfit.core.io.json_file import read_json, write_json
from dolphinfit.core.limits import FOCAL_MM, IMAGE_SIZE_PX, SENSOR_WIDTH_MM, in_range
from dolphinfit.core.resources import resource_path

PRESETS_FILE = "cameras.json"  # bundled in resources/, and the user file's name
PRESETS_SCHEMA_VERSION = 1
DEFAULT_PRESET = "dji-mavic3-5.1k"  # the paper's camera and video mode (arXiv 2504.15782)
CONFIG_DIR_ENV = "DOLPHINFIT_CONFIG_DIR"  # overrides the XDG location of the user config
XDG_CONFIG_ENV = "XDG_CONFIG_HOME"
XDG_CONFIG_DEFAULT = Path("~/.config")
MAKER_WORDS = 1  # a preset's model may start with the maker's name ("DJI Mavic Air 2")
# a table states no image height; it enters no altitude calibration (the focal length in
# pixels is the width's), so drone video's 16:9 stands in
TABLE_HEIGHT_PER_WIDTH = 9 / 16  # XDG Base Directory specification default
CONFIG_SUBDIR = "dolphinfit"


@dataclass(frozen=True)
class CameraPreset:
    """A named drone camera and video mode: sensor width read in that mode, real focal length.

    ``approximate``: the values are not verified for this mode (e.g. nominal specifications).
    """

    name: str
    description: str
    focal_mm: float
    sensor_width_mm: float
    image_width_px: int
    image_height_px: int
    source: str
    approximate: bool

    def __post_init__(self) -> None:
        if not self.name.strip():
            raise ValueError("name must not be empty")
        for name in ("focal_mm", "sensor_width_mm", "image_width_px", "image_height_px"):
            require_positive(name, getattr(self, name))

    def intrinsics(self) -> CameraIntrinsics:
        """Full-frame intrinsics of this mode (centred principal point)."""
        return CameraIntrinsics.from_sensor(
            self.focal_mm, self.sensor_width_mm, self.image_width_px, self.image_height_px
        )


# JSON types accepted per field (a JSON number such as 12 is fine for a float field)
_PRESET_TYPES: dict[str, tuple[type, ...]] = {
    f.name: (int, float) if f.type is float else (f.type,) for f in fields(CameraPreset)
}


def preset_resolution_mismatch(preset: CameraPreset, width_px: int, height_px: int) -> str | None:
    """A warning sentence when ``preset``'s image size is not the clip's; None when it is.

    The focal length in pixels, hence every length, holds only at the preset's image size.
    """
    if (preset.image_width_px, preset.image_height_px) == (width_px, height_px):
        return None
    return (f"camera preset {preset.name!r} is for {preset.image_width_px}×"
            f"{preset.image_height_px} px images but the clip is {width_px}×{height_px} px: "
            f"choose the preset of the clip's video mode, or lengths will be wrong")


def config_dir() -> Path:
    """The folder of the user's configuration (camera presets, recent files).

    ``$DOLPHINFIT_CONFIG_DIR``, else ``$XDG_CONFIG_HOME/dolphinfit``; ``XDG_CONFIG_HOME``
    defaults to ``~/.config``.
    """
    configured = os.environ.get(CONFIG_DIR_ENV)
    if configured:
        return Path(configured)
    xdg_home = os.environ.get(XDG_CONFIG_ENV) or str(XDG_CONFIG_DEFAULT)
    return Path(xdg_home).expanduser() / CONFIG_SUBDIR


def user_presets_path() -> Path:
    """The user's presets file: ``cameras.json`` in :func:`config_dir`."""
    return config_dir() / PRESETS_FILE


def _preset_from_json(entry: Any, path: Path, index: int) -> CameraPreset:
    """One preset object of a presets file; InputError naming the file and entry otherwise."""
    where = f"{path}: preset #{index}"
    if not isinstance(entry, dict):
        raise InputError(f"{where}: expected an object, got {type(entry).__name__}")
    if isinstance(entry.get("name"), str):
        where += f" ({entry['name']!r})"
    missing = [key for key in _PRESET_TYPES if key not in entry]
    unknown = sorted(set(entry) - set(_PRESET_TYPES))
    if missing or unknown:
        raise InputError(f"{where}: missing fields {missing}, unknown fields {unknown}")
    for key, types in _PRESET_TYPES.items():
        value = entry[key]
        if not isinstance(value, types) or (isinstance(value, bool) and bool not in types):
            raise InputError(f"{where}: field {key!r} has the wrong type ({value!r})")
    try:
        return CameraPreset(**entry)
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from exc


def _read_presets_file(path: Path) -> list[CameraPreset]:
    """All presets of one file, in order; InputError naming the file when it is malformed."""
    data = read_json(path, "camera presets")
    if not isinstance(data, dict) or set(data) != {"schema_version", "presets"}:
        raise InputError(f"{path}: expected an object with 'schema_version' and 'presets' only")
    if data["schema_version"] != PRESETS_SCHEMA_VERSION:
        raise InputError(
            f"{path}: schema_version {data['schema_version']!r} is not supported "
            f"(expected {PRESETS_SCHEMA_VERSION})"
        )
    if not isinstance(data["presets"], list):
        raise InputError(f"{path}: 'presets' must be a list")
    presets = [_preset_from_json(entry, path, i) for i, entry in enumerate(data["presets"])]
    names = [preset.name for preset in presets]
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        raise InputError(f"{path}: duplicate preset names {duplicates}")
    return presets


def load_presets(user_path: Path | None = None) -> dict[str, CameraPreset]:
    """Bundled presets merged with the user's (``user_presets_path()`` by default).

    User entries override bundled ones of the same name; a missing user file is no error.
    """
    user_path = user_presets_path() if user_path is None else user_path
    presets = {p.name: p for p in _read_presets_file(resource_path(PRESETS_FILE))}
    if user_path.exists():
        presets.update((p.name, p) for p in _read_presets_file(user_path))
    return presets


def get_preset(name: str, user_path: Path | None = None) -> CameraPreset:
    """The preset called ``name``; InputError listing the available names otherwise."""
    presets = load_presets(user_path)
    if name not in presets:
        raise InputError(
            f"unknown camera preset {name!r}; available: {', '.join(sorted(presets))}"
        )
    return presets[name]


def save_user_preset(preset: CameraPreset, user_path: Path | None = None) -> Path:
    """Add ``preset`` to the user presets file, replacing one of that name; returns the path.

    The file is rewritten atomically (temporary file, then rename); a malformed existing file
    raises InputError and is left untouched.
    """
    user_path = user_presets_path() if user_path is None else user_path
    existing = _read_presets_file(user_path) if user_path.exists() else []
    kept = [p for p in existing if p.name != preset.name]
    data = {
        "schema_version": PRESETS_SCHEMA_VERSION,
        "presets": [asdict(p) for p in [*kept, preset]],
    }
    write_json(user_path, data)
    return user_path


def _words(text: str) -> list[str]:
    """Lower-case words, a number split from letters before it ("Mavic3" → mavic, 3;
    "2.7K" → 2.7k)."""
    return re.findall(r"[a-z]+|\d+(?:\.\d+)?[a-z]*", text.lower())


def _contains(words: list[str], part: list[str]) -> bool:
    return any(words[i:i + len(part)] == part for i in range(len(words) - len(part) + 1))


def _is_model(text: str, drone: list[str], mode: list[str]) -> bool:
    """Whether ``text`` names just the drone ``drone``: its words, the maker's name before them
    and the video mode ``mode`` after them optional ("dji-mavic3-2.7k" is "Mavic 3", but
    "DJI Mavic Air 2S" is not "Mavic Air 2")."""
    words = _words(text)
    if words[len(words) - len(mode):] == mode:
        words = words[:len(words) - len(mode)]
    return words[len(words) - len(drone):] == drone and len(words) - len(drone) <= MAKER_WORDS


def preset_for_drone(drone: str, video_mode: str,
                     presets: dict[str, CameraPreset]) -> CameraPreset | None:
    """The camera of ``drone`` (e.g. "Mavic Air 2") in ``video_mode`` (e.g. "2.7k") among
    ``presets``: those whose name, or description before its first comma, is that drone, and
    whose name or description names the mode. None unless they are all one camera (the same
    focal length, sensor width and image width)."""
    drone_words, mode_words = _words(drone), _words(video_mode)
    if not drone_words or not mode_words:
        return None
    found = [preset for preset in presets.values()
             if (_is_model(preset.name, drone_words, mode_words)
                 or _is_model(preset.description.split(",")[0], drone_words, mode_words))
             and (_contains(_words(preset.name), mode_words)
                  or _contains(_words(preset.description), mode_words))]
    cameras = {(p.focal_mm, p.sensor_width_mm, p.image_width_px) for p in found}
    return found[0] if len(cameras) == 1 else None


def table_camera(table: CalibrationTable,
                 presets: dict[str, CameraPreset]) -> tuple[CameraPreset, str] | None:
    """The camera a calibration table's shots were taken with, and where it was found: the
    table's focal length, sensor width and image width columns, else the preset of its drone
    and video mode (:func:`preset_for_drone`). None when the table states neither, or only
    part of its camera; InputError naming the file when its rows disagree or a value is
    implausible."""
    where = table.path.name
    values = [table.common_value(name)
              for name in ("focal_mm", "sensor_width_mm", "image_width_px")]
    if all(value is not None for value in values):
        focal_mm, sensor_mm, width = (
            in_range(value, limits, f"{table.path}: {name}") for value, limits, name in zip(
                values, (FOCAL_MM, SENSOR_WIDTH_MM, IMAGE_SIZE_PX),
                ("focal_mm", "sensor_width_mm", "image_width_px")))
        width_px = int(round(width))
        camera = CameraPreset(
            name=table.drone or table.path.stem,
            description=f"the camera in {where}'s columns (which give no image height)",
            focal_mm=focal_mm, sensor_width_mm=sensor_mm, image_width_px=width_px,
            image_height_px=round(width_px * TABLE_HEIGHT_PER_WIDTH), source=str(table.path),
            approximate=False)
        return camera, f"{where}'s columns"
    if any(value is not None for value in values):
        return None
    preset = preset_for_drone(table.drone, table.resolution, presets)
    if preset is None:
        return None
    return preset, f"preset {preset.name!r}: {where} names {table.drone} at {table.resolution}"
