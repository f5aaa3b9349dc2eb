"""The nadir drone camera: intrinsics, presets, crops, per-frame altitude and refraction.

Frames (DESIGN.md §3):

- **World**: right-handed, metres, z up. The water surface is the plane z = 0; submerged points
  have z < 0. For frame t the camera sits at (0, 0, h_t), h_t = ``altitude_m[t]`` > 0, and looks
  straight down (nadir).
- **Camera** (OpenCV): origin at the camera, X_cam = x, Y_cam = −y, Z_cam = h − z (depth along
  the optical axis, which points straight down). No rotation ever enters: the camera is nadir.
- **Pixel**: OpenCV convention. Pixel centres lie at integer coordinates, (0, 0) is the centre of
  the top-left pixel, column u grows to the right, row v grows downwards. Image +u is world +x and
  image +v (down) is world −y. The principal point (cx, cy) is the pixel straight below the camera.

A straight (no refraction) projection of a world point (x, y, z) is

    u = cx + f·x / (h − z),    v = cy − f·y / (h − z).

A region-of-interest crop with top-left pixel (x0, y0) of the full frame is the same camera with
principal point (cx − x0, cy − y0): metric scale is untouched.

Refraction: light from a submerged point Q bends where it crosses the flat water surface
(Snell's law, n_air·sinθ_air = n_water·sinθ_water). With refraction on, Q is imaged at its
*apparent surface point* S, the point of z = 0 where its light path to the camera crosses the
surface, and S projects straight.

Batches: inputs carry a leading frame axis of size 1 or T (the camera's number of altitudes);
anything else raises ValueError giving both counts. Everything here is differentiable torch and
takes its dtype and device from its inputs.
"""

import math
import os
from collections.abc import Sequence
from dataclasses import asdict, dataclass, fields, replace
from pathlib import Path
from typing import Any, Self

import torch

from core.errors import InputError
from core.io.json_file import read_json, write_json
from core.resources import resource_path

N_WATER = 1.333  # refractive index of (sea) water, DESIGN.md §3
N_AIR = 1.0  # air taken as 1: DESIGN.md §3's n_water is relative to air

# Newton solve for the apparent surface point; the unknown is the fraction s ∈ [0, 1] of the
# way from the camera nadir to the point's horizontal position, so tolerances are relative.
SURFACE_SOLVE_TOL = 1e-13  # stop when every Newton step is below this (float64 spacing ~1e-16)
SURFACE_SOLVE_MAX_ITER = 64  # bisection fallback halves a [0, 1] bracket: 64 halvings < 1e-19

PRESETS_FILE = "cameras.json"  # bundled in resources/, and the user file's name
PRESETS_SCHEMA_VERSION = 1
DEFAULT_PRESET = "dji-mavic3-5.1k"  # the paper's camera and video mode (arXiv 2504.15782)
CONFIG_DIR_ENV = "DOLPHINFIT_CONFIG_DIR"  # overrides the XDG location of the user presets
XDG_CONFIG_ENV = "XDG_CONFIG_HOME"
XDG_CONFIG_DEFAULT = Path("~/.config")  # XDG Base Directory specification default
CONFIG_SUBDIR = "dolphinfit"


# --------------------------------------------------------------------------------------------
# Intrinsics


def _require_positive(name: str, value: float) -> None:
    """Raise ValueError naming ``name`` unless ``value`` is a finite number > 0."""
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")


@dataclass(frozen=True)
class CameraIntrinsics:
    """Pinhole intrinsics in pixels, square pixels (fx = fy), no distortion.

    ``focal_px``: focal length in pixels; ``cx_px``, ``cy_px``: principal point (pixel frame,
    may lie outside the image for a crop); ``width_px``, ``height_px``: image size.
    """

    focal_px: float
    cx_px: float
    cy_px: float
    width_px: int
    height_px: int

    def __post_init__(self) -> None:
        _require_positive("focal_px", self.focal_px)
        _require_positive("width_px", self.width_px)
        _require_positive("height_px", self.height_px)
        for name in ("cx_px", "cy_px"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be finite, got {getattr(self, name)!r}")

    @classmethod
    def from_sensor(
        cls, focal_mm: float, sensor_width_mm: float, image_width_px: int, image_height_px: int
    ) -> Self:
        """f = focal_mm / sensor_width_mm × image_width_px (DESIGN.md §3), centred principal point.

        ``sensor_width_mm`` is the width of the sensor area the video mode reads.
        """
        _require_positive("focal_mm", focal_mm)
        _require_positive("sensor_width_mm", sensor_width_mm)
        _require_positive("image_width_px", image_width_px)
        _require_positive("image_height_px", image_height_px)
        return cls(
            focal_px=focal_mm / sensor_width_mm * image_width_px,
            cx_px=(image_width_px - 1) / 2,
            cy_px=(image_height_px - 1) / 2,
            width_px=image_width_px,
            height_px=image_height_px,
        )

    @property
    def fov_x_rad(self) -> float:
        """Horizontal field of view, 2·atan(W / 2f), radians (the paper's 2·atan(γ / 2ω))."""
        return 2 * math.atan(self.width_px / (2 * self.focal_px))

    @property
    def fov_y_rad(self) -> float:
        """Vertical field of view, 2·atan(H / 2f), radians."""
        return 2 * math.atan(self.height_px / (2 * self.focal_px))

    def gsd_m_per_px(self, altitude_m: float) -> float:
        """Ground sampling distance on the water plane at ``altitude_m``: h / f, metres/pixel."""
        return altitude_m / self.focal_px

    def crop(self, x0_px: int, y0_px: int, width_px: int, height_px: int) -> Self:
        """The region with top-left pixel (x0, y0) and the given size; it may exceed the image."""
        return replace(
            self, cx_px=self.cx_px - x0_px, cy_px=self.cy_px - y0_px,
            width_px=width_px, height_px=height_px,
        )

    def resized(self, width_px: int, height_px: int) -> Self:
        """Intrinsics of the whole image rescaled to ``width_px`` × ``height_px``.

        With s = new / old width, pixel centres map as c' = (c + 0.5)·s − 0.5 and f' = f·s. Square
        pixels need one scale for both axes, so the new height must match the old aspect within
        1 px (the rounding of the height is then at most half a pixel at the border).
        """
        scale = width_px / self.width_px
        if abs(height_px - self.height_px * scale) > 1:
            raise ValueError(
                f"resizing {self.width_px}×{self.height_px} px to {width_px}×{height_px} px "
                f"changes the aspect ratio by more than 1 px"
            )
        return replace(
            self,
            focal_px=self.focal_px * scale,
            cx_px=(self.cx_px + 0.5) * scale - 0.5,
            cy_px=(self.cy_px + 0.5) * scale - 0.5,
            width_px=width_px,
            height_px=height_px,
        )


# --------------------------------------------------------------------------------------------
# Refraction at a flat water surface


def _snell_residual(
    frac: torch.Tensor, rho_sq: torch.Tensor, h: torch.Tensor, d: torch.Tensor, n: float
) -> tuple[torch.Tensor, torch.Tensor]:
    """g(s) = sinθ_air/ρ − n·sinθ_water/ρ and its derivative g'(s) > 0, for S at r = s·ρ.

    g(s) = s/√(s²ρ² + h²) − n(1 − s)/√((1 − s)²ρ² + d²) is Snell's residual divided by ρ, so it
    stays smooth at ρ = 0 (where its root is the paraxial s = n·h/(d + n·h)).
    """
    air_sq = (frac * frac) * rho_sq + h * h
    water_sq = (1 - frac) ** 2 * rho_sq + d * d
    residual = frac * torch.rsqrt(air_sq) - n * (1 - frac) * torch.rsqrt(water_sq)
    slope = h * h * air_sq.pow(-1.5) + n * d * d * water_sq.pow(-1.5)
    return residual, slope


def _solve_surface_fraction(
    rho_sq: torch.Tensor, h: torch.Tensor, d: torch.Tensor, n: float
) -> torch.Tensor:
    """Root s ∈ [0, 1] of g (see ``_snell_residual``) by safeguarded Newton; no autograd.

    Starts from the paraxial guess; keeps a bracket [lo, hi] (g increases in s) and bisects
    whenever a Newton step would leave it.
    """
    frac = n * h / (d + n * h)
    if frac.numel() == 0:
        return frac
    lo, hi = torch.zeros_like(frac), torch.ones_like(frac)
    for _ in range(SURFACE_SOLVE_MAX_ITER):
        residual, slope = _snell_residual(frac, rho_sq, h, d, n)
        is_below_root = residual < 0
        lo = torch.where(is_below_root, frac, lo)
        hi = torch.where(is_below_root, hi, frac)
        newton = frac - residual / slope
        new_frac = torch.where((newton >= lo) & (newton <= hi), newton, (lo + hi) / 2)
        max_step = (new_frac - frac).abs().max()
        frac = new_frac
        if max_step <= SURFACE_SOLVE_TOL:
            break
    return frac


def apparent_surface_point(
    points_world: torch.Tensor, altitude_m: torch.Tensor | float, n_water: float = N_WATER
) -> torch.Tensor:
    """Where light from each submerged point to the camera crosses the water surface (exact).

    points_world: (..., 3) float, metres, world frame. altitude_m: camera height(s) h > 0,
    metres, broadcastable to ``points_world.shape[:-1]``. Returns (..., 3) in the input dtype:
    for z < 0 the point S = (s·x, s·y, 0) on z = 0 with sinθ_air = n·sinθ_water (n relative to
    air), 0 ≤ s ≤ 1; points with z ≥ 0 unchanged.

    The root is found in float64 without autograd; one final Newton step from the detached root,
    with autograd on, gives exactly the implicit-function-theorem gradient.
    """
    n = n_water / N_AIR
    points = points_world.to(torch.float64)
    h = torch.as_tensor(altitude_m, dtype=torch.float64, device=points.device)
    x, y, z, h = torch.broadcast_tensors(*points.unbind(-1), h)
    if bool((h <= 0).any()):
        raise ValueError("altitude_m must be positive (the camera is above the water)")
    is_submerged = z < 0
    depth = torch.where(is_submerged, -z, torch.ones_like(z))  # safe (unused) value above water
    rho_sq = x * x + y * y
    with torch.no_grad():
        frac = _solve_surface_fraction(rho_sq, h, depth, n)
    residual, slope = _snell_residual(frac, rho_sq, h, depth, n)
    frac = frac - residual / slope  # ≈ frac in value; carries d(root)/d(inputs)
    surface = torch.stack((x * frac, y * frac, torch.zeros_like(z)), dim=-1)
    apparent = torch.where(is_submerged.unsqueeze(-1), surface, torch.stack((x, y, z), dim=-1))
    return apparent.to(points_world.dtype)


# --------------------------------------------------------------------------------------------
# The camera over T frames


@dataclass(frozen=True, eq=False)
class NadirCamera:
    """A nadir camera over T frames: shared intrinsics, one altitude per frame.

    ``altitude_m``: (T,) float, metres above the water surface, > 0. ``refraction``: image
    submerged points through a flat water surface (Snell's law) instead of straight lines.
    ``n_water``: refractive index of water relative to air. Inputs may be batched over 1 or T
    frames. (``eq=False``: tensors have no single truth value, so instances compare by identity.)
    """

    intrinsics: CameraIntrinsics
    altitude_m: torch.Tensor
    refraction: bool = True
    n_water: float = N_WATER

    def __post_init__(self) -> None:
        if self.altitude_m.dim() != 1 or self.altitude_m.numel() == 0:
            raise ValueError(
                f"altitude_m must have shape (T,) with T ≥ 1, got {tuple(self.altitude_m.shape)}"
            )
        if not bool(torch.isfinite(self.altitude_m).all() and (self.altitude_m > 0).all()):
            raise ValueError("altitude_m must be positive and finite in every frame")
        if not self.n_water >= N_AIR:
            raise ValueError(f"n_water must be at least {N_AIR}, got {self.n_water!r}")

    @property
    def num_frames(self) -> int:
        """T, the number of frames (altitudes)."""
        return self.altitude_m.shape[0]

    def _check_batch(self, num_input_frames: int, what: str) -> None:
        """Raise ValueError, giving both counts, unless the input has 1 or T frames."""
        if num_input_frames not in (1, self.num_frames):
            raise ValueError(
                f"{what} have {num_input_frames} frames but the camera has {self.num_frames} "
                f"altitudes; a batch must have 1 frame or as many as the camera"
            )

    def _frames_batch(self, values: torch.Tensor, width: int, what: str) -> torch.Tensor:
        """``values`` as (T | 1, N, width): adds the frame axis to (N, width), checks the batch."""
        batch = values.unsqueeze(0) if values.dim() == 2 else values
        if batch.dim() != 3 or batch.shape[-1] != width:
            raise ValueError(f"{what} must have shape (T, N, {width}) or (N, {width}), "
                             f"got {tuple(values.shape)}")
        self._check_batch(batch.shape[0], what)
        return batch

    def _altitudes_like(self, tensor: torch.Tensor) -> torch.Tensor:
        """(T, 1) altitudes in ``tensor``'s dtype and device."""
        return self.altitude_m.to(dtype=tensor.dtype, device=tensor.device).unsqueeze(-1)

    def project(self, points_world: torch.Tensor) -> torch.Tensor:
        """World points to pixels.

        points_world: (T, N, 3), (1, N, 3) or (N, 3) float, metres, world frame. Returns
        (T', N, 2) pixel coordinates (u, v), T' = max(point frames, T). With refraction on,
        submerged points are imaged at their apparent surface point. Raises ValueError for a
        point at or above the camera.
        """
        points = self._frames_batch(points_world, 3, "points")
        h = self._altitudes_like(points)
        if bool((points[..., 2].detach() >= h.detach()).any()):
            raise ValueError("a point is at or above the camera (z ≥ altitude_m)")
        if self.refraction:
            points = apparent_surface_point(points, h, self.n_water)
        x, y, z = points.unbind(-1)
        depth = h - z  # distance below the camera along its axis, metres
        k = self.intrinsics
        u_px = k.cx_px + k.focal_px * x / depth
        v_px = k.cy_px - k.focal_px * y / depth  # image +v is world −y
        return torch.stack((u_px, v_px), dim=-1)

    def unproject(
        self, xy_px: torch.Tensor, plane_z_m: float | torch.Tensor = 0.0
    ) -> torch.Tensor:
        """Pixels to world points on the horizontal plane z = ``plane_z_m``.

        xy_px: (T, N, 2), (1, N, 2) or (N, 2) float pixel coordinates (u, v). plane_z_m: metres,
        a float or a (T,) tensor, below the camera. Returns (T', N, 3), metres, world frame. With
        refraction on and the plane under water, the viewing ray bends at the surface.
        """
        xy = self._frames_batch(xy_px, 2, "pixels")
        h = self._altitudes_like(xy)
        plane_z = torch.as_tensor(plane_z_m, dtype=xy.dtype, device=xy.device).reshape(-1, 1)
        self._check_batch(plane_z.shape[0], "plane heights")
        if bool((plane_z.detach() >= h.detach()).any()):
            raise ValueError("plane_z_m must lie below the camera (plane_z_m < altitude_m)")
        k = self.intrinsics
        # viewing ray: horizontal offset per metre below the camera (image +v is world −y)
        ray_x = (xy[..., 0] - k.cx_px) / k.focal_px
        ray_y = (k.cy_px - xy[..., 1]) / k.focal_px
        reach = self._ray_reach(ray_x * ray_x + ray_y * ray_y, h, plane_z)
        return torch.stack(torch.broadcast_tensors(ray_x * reach, ray_y * reach, plane_z), dim=-1)

    def _ray_reach(
        self, tan_sq: torch.Tensor, h: torch.Tensor, plane_z: torch.Tensor
    ) -> torch.Tensor:
        """Horizontal distance travelled per unit of ray slope down to z = plane_z, metres.

        Straight: h − z. Refracted below the surface: h + d·tanθ_w / tanθ_a with d = −z, where
        tanθ_w / tanθ_a = cosθ_a / (n·cosθ_w) stays finite at the nadir.
        """
        if not self.refraction:
            return h - plane_z
        n = self.n_water / N_AIR
        cos_air = torch.rsqrt(1 + tan_sq)
        cos_water = torch.sqrt(1 - tan_sq / (1 + tan_sq) / (n * n))
        above, below = plane_z.clamp(min=0), (-plane_z).clamp(min=0)
        return h - above + below * cos_air / (n * cos_water)

    def select(self, frame_idx: int | Sequence[int] | torch.Tensor) -> Self:
        """The camera for the given frames (an index or a 1-D index list/tensor)."""
        idx = torch.as_tensor(frame_idx, dtype=torch.long, device=self.altitude_m.device)
        return replace(self, altitude_m=self.altitude_m[idx.reshape(-1)])

    def crop(self, x0_px: int, y0_px: int, width_px: int, height_px: int) -> Self:
        """The same camera seeing only the region with top-left pixel (x0, y0) and that size."""
        return replace(self, intrinsics=self.intrinsics.crop(x0_px, y0_px, width_px, height_px))

    def gsd_m_per_px(self) -> torch.Tensor:
        """(T,) ground sampling distance on the water plane per frame, metres per pixel."""
        return self.altitude_m / self.intrinsics.focal_px


# --------------------------------------------------------------------------------------------
# Presets


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
            _require_positive(name, getattr(self, name))

    def intrinsics(self) -> CameraIntrinsics:
        """Full-frame intrinsics of this mode (centred principal point)."""
        return CameraIntrinsics.from_sensor(
            self.focal_mm, self.sensor_width_mm, self.image_width_px, self.image_height_px
        )


# JSON types accepted per field (a JSON number such as 12 is fine for a float field)
_PRESET_TYPES: dict[str, tuple[type, ...]] = {
    f.name: (int, float) if f.type is float else (f.type,) for f in fields(CameraPreset)
}


def user_presets_path() -> Path:
    """``$DOLPHINFIT_CONFIG_DIR/cameras.json``, else ``$XDG_CONFIG_HOME/dolphinfit/cameras.json``.

    ``XDG_CONFIG_HOME`` defaults to ``~/.config``.
    """
    config_dir = os.environ.get(CONFIG_DIR_ENV)
    if config_dir:
        return Path(config_dir) / PRESETS_FILE
    xdg_home = os.environ.get(XDG_CONFIG_ENV) or str(XDG_CONFIG_DEFAULT)
    return Path(xdg_home).expanduser() / CONFIG_SUBDIR / PRESETS_FILE


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

