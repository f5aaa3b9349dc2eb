"""The nadir drone camera: intrinsics, crops, per-frame altitude and refraction.

Named cameras (presets) and the user's presets file are in core/camera_presets.py; pinhole
intrinsics (focal length in pixels, crops, GSD) in core/intrinsics.py, which needs no torch.

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

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Self

import torch

from dolphinfit.core.intrinsics import CameraIntrinsics

N_WATER = 1.333  # refractive index of (sea) water, DESIGN.md §3
N_AIR = 1.0  # air taken as 1: DESIGN.md §3's n_water is relative to air

# Newton solve for the apparent surface point; the unknown is the fraction s ∈ [0, 1] of the
# way from the camera nadir to the point's horizontal position, so tolerances are relative.
SURFACE_SOLVE_TOL = 1e-13  # stop when every Newton step is below this (float64 spacing ~1e-16)
SURFACE_SOLVE_MAX_ITER = 64  # bisection fallback halves a [0, 1] bracket: 64 halvings < 1e-19


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
