"""Pinhole intrinsics of the nadir drone camera, in pixels: focal length from the sensor the
video mode reads, principal point, crops and resizes, ground sampling distance.

Plain Python (no torch), so the app and the file readers can use it without loading the
fitting stack; the projection and refraction that need gradients are in core/camera.py.
"""

import math
from dataclasses import dataclass, replace
from typing import Self


def require_positive(name: str, value: float) -> None:
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
        require_positive("focal_px", self.focal_px)
        require_positive("width_px", self.width_px)
        require_positive("height_px", self.height_px)
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
        require_positive("focal_mm", focal_mm)
        require_positive("sensor_width_mm", sensor_width_mm)
        require_positive("image_width_px", image_width_px)
        require_positive("image_height_px", image_height_px)
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

    def binned(self, factor: int) -> Self:
        """Intrinsics of the image whose pixels are ``factor`` × ``factor`` blocks of this
        one's, from its top-left pixel (a last part block dropped): centres map as
        c' = (c + 0.5) / factor − 0.5 and f' = f / factor whatever the image's size (a still
        1985 rows high included)."""
        return replace(self, focal_px=self.focal_px / factor,
                       cx_px=(self.cx_px + 0.5) / factor - 0.5,
                       cy_px=(self.cy_px + 0.5) / factor - 0.5,
                       width_px=self.width_px // factor, height_px=self.height_px // factor)

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
