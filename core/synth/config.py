"""What a synthetic clip shows: camera, animal, motion, water, light, sensor and effects.

Every field has a unit in its name and a default; ``SynthConfig`` round-trips through JSON so
``truth.json`` records exactly how its clip was made.
"""

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.json_file import dataclass_from_json
from dolphinfit.core.measure.hw_ratios import preset_names
from dolphinfit.core.limits import (
    ALTITUDE_M, BODY_LENGTH_M, FOCAL_MM, FPS, IMAGE_SIZE_PX, LAUNCH_HEIGHT_M, SENSOR_WIDTH_MM,
    check_fields, one_of,
)

RANGES = {"altitude_m": ALTITUDE_M, "length_m": BODY_LENGTH_M, "focal_mm": FOCAL_MM,
          "sensor_width_mm": SENSOR_WIDTH_MM, "width_px": IMAGE_SIZE_PX,
          "height_px": IMAGE_SIZE_PX, "fps": FPS, "launch_height_m": LAUNCH_HEIGHT_M}
MINIMUMS = {name: 0.0 for name in ("seed", "altitude_drift_m", "shape_sd", "speed_m_s",
                                   "stroke_hz", "stroke_amplitude", "surface_depth_m",
                                   "dive_depth_m", "noise_sd", "blur_px")}

COLOURATIONS = ("dark", "light_grey")
CODECS = ("mp4v", "h264")        # lossy video: OpenCV's MPEG-4 part 2, or H.264 as drones record
TEMPLATE_BODY = "template"
# the template's family, or a foreign body (core.synth.foreign.FOREIGN_BODIES, in this order)
BODIES = (TEMPLATE_BODY, "robust", "slender", "keeled")
SUPERSAMPLE = (1, 8)             # rendered at up to 8× the delivered frame size
SECTION_EXPONENT = (1.5, 3.0)   # cross-sections from lean lozenges to near-rectangles


@dataclass(frozen=True)
class Effects:
    """What the fit does not model, each switchable (all on = hardest, most realistic)."""

    profile_warp: bool = True    # smooth random change of width/height profiles (outside β)
    finer_mesh: bool = False     # Loop-subdivided, smoother surface than the fitted template
    scattering: bool = True      # water adds its own colour with depth, not only attenuation
    refraction: bool = True      # flat-surface refraction of submerged parts
    ripples: bool = True         # surface waves warp the submerged image
    glints: bool = True          # sun glints on the water, over the animal too
    compression: bool = True     # lossy mp4v video instead of lossless FFV1


@dataclass(frozen=True)
class SynthConfig:
    """A synthetic clip. Lengths in metres, angles in degrees at this boundary, times in s."""

    seed: int = 0
    width_px: int = 1920
    height_px: int = 1080
    fps: float = 25.0
    duration_s: float = 4.0
    focal_mm: float = 12.29                 # the paper's camera (DESIGN.md §3)
    sensor_width_mm: float = 17.27
    altitude_m: float = 20.0
    altitude_drift_m: float = 0.3           # slow sinusoidal change over the clip
    launch_height_m: float = 1.5            # SRT rel_alt is altitude minus this
    length_m: float = 2.5
    shape_sd: float = 0.05                  # SD of each random log part scale
    speed_m_s: float = 1.6
    heading_deg: float | None = None        # None: random
    turn_deg_s: float = 4.0
    stroke_hz: float = 1.2
    stroke_amplitude: float = 1.0           # 1 = a cruising stroke
    surface_depth_m: float = 0.12           # root depth while cruising (back at the surface)
    dive_depth_m: float = 0.6               # extra depth at the bottom of the dive
    roll_deg: float = 4.0
    water_rgb: tuple[float, float, float] = (0.06, 0.26, 0.30)
    clarity_per_m: tuple[float, float, float] = (0.55, 0.18, 0.14)   # attenuation, 1/m
    sea_state: float = 0.3                  # 0 glassy … 1 rough
    sun_elevation_deg: float = 60.0
    sun_azimuth_deg: float = 30.0
    noise_sd: float = 0.01                  # sensor noise, fraction of full scale
    blur_px: float = 0.6                    # optical blur, Gaussian σ
    colouration: str = "dark"               # "dark" (the template's albedo) or "light_grey"
    seabed_depth_m: float | None = None     # a visible seabed this deep; None: open water
    seabed_rgb: tuple[float, float, float] = (0.72, 0.66, 0.50)   # bare sand
    seabed_cover: float = 0.0               # fraction of the bed under dark seagrass patches
    glitter: float = 0.0                    # capillary-wave sun glitter, 0 off … 1 heavy
    wet_specular: float = 0.0               # highlight on the wet skin above water, 0 off
    turn_flex: float = 0.0                  # lateral flex; 1 = the body bends with the path
    companion_offset_m: float | None = None  # a second animal this far to the left (− right)
    companion_ahead_m: float = 0.0          # … and this far ahead of the target
    companion_length_m: float = 2.4
    splash: float = 0.0                     # white water and wake at the surface, 0 off … 1
    # The animal's cross-sections (core/model/sections.py): its heights are its widths times
    # ratios drawn from this HW preset's ratios and SDs (the random part scales and profile
    # warp then change widths and heights together); None: the template's heights, with
    # part scales and warp drawn for each axis apart. Sections are superellipses of
    # section_exponent (2: ellipses, as the template's; larger fuller, smaller leaner).
    hw_table: str | None = None
    section_exponent: float = 2.0
    # "template", or one of core.synth.foreign's bodies: animals not of the template's family
    # (another width profile, beak, heights and fins), for a split the fit was never tuned on
    body: str = TEMPLATE_BODY
    # the frame rendered at this many times width_px × height_px and downscaled by area, as a
    # 5K camera's video delivered at 720p (the camera's focal length in mm is unchanged)
    supersample: int = 1
    codec: str = "mp4v"                     # lossy codec (CODECS) when effects.compression
    bitrate_mbps: float = 20.0              # H.264's target bit rate (mp4v has its own)
    crf: int | None = None                  # H.264 at this constant rate factor instead
    body_contrast: float = 1.0              # the animal's difference from the water, scaled
    effects: Effects = field(default_factory=Effects)

    def __post_init__(self) -> None:
        check_fields(self, "synth option ", ranges=RANGES, minimum=MINIMUMS)
        positive = ("width_px", "height_px", "fps", "duration_s", "focal_mm", "sensor_width_mm",
                    "altitude_m", "length_m", "speed_m_s")
        for name in positive:
            if not getattr(self, name) > 0:
                raise InputError(f"synth option {name}: must be positive, "
                                 f"got {getattr(self, name)!r}")
        if self.width_px % 2 or self.height_px % 2:
            raise InputError(f"synth image size {self.width_px}×{self.height_px}: "
                             f"width and height must be even for the video encoder")
        for name in ("sea_state", "seabed_cover", "glitter", "splash"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise InputError(f"synth option {name}: must lie in [0, 1], "
                                 f"got {getattr(self, name)}")
        one_of(self.colouration, COLOURATIONS, "synth option colouration")
        one_of(self.codec, CODECS, "synth option codec")
        one_of(self.body, BODIES, "synth option body")
        if not (isinstance(self.supersample, int)
                and SUPERSAMPLE[0] <= self.supersample <= SUPERSAMPLE[1]):
            raise InputError(f"synth option supersample: a whole number in "
                             f"{SUPERSAMPLE[0]}–{SUPERSAMPLE[1]}, got {self.supersample!r}")
        if self.crf is not None and not (isinstance(self.crf, int) and 0 <= self.crf <= 51):
            raise InputError(f"synth option crf: a whole number in 0–51, got {self.crf!r}")
        if not 0.0 < self.body_contrast <= 2.0:
            raise InputError(f"synth option body_contrast: must lie in (0, 2], "
                             f"got {self.body_contrast!r}")
        if not self.bitrate_mbps > 0:
            raise InputError(f"synth option bitrate_mbps: must be positive, "
                             f"got {self.bitrate_mbps!r}")
        if self.hw_table is not None:
            one_of(self.hw_table, tuple(preset_names()), "synth option hw_table")
        if not SECTION_EXPONENT[0] <= self.section_exponent <= SECTION_EXPONENT[1]:
            raise InputError(f"synth option section_exponent: must lie in "
                             f"[{SECTION_EXPONENT[0]}, {SECTION_EXPONENT[1]}], "
                             f"got {self.section_exponent}")
        for name in ("seabed_depth_m", "companion_length_m"):
            value = getattr(self, name)
            if value is not None and not value > 0:
                raise InputError(f"synth option {name}: must be positive, got {value!r}")

    def sun_direction(self) -> np.ndarray:
        """(3,) unit vector towards the sun, world frame (z up)."""
        elevation = math.radians(self.sun_elevation_deg)
        azimuth = math.radians(self.sun_azimuth_deg)
        return np.array([math.cos(elevation) * math.cos(azimuth),
                         math.cos(elevation) * math.sin(azimuth), math.sin(elevation)])

    @property
    def num_frames(self) -> int:
        """Frames in the clip."""
        return max(1, int(round(self.duration_s * self.fps)))

    def to_json(self) -> dict:
        """JSON-ready dict."""
        return asdict(self)

    @classmethod
    def from_json(cls, data: dict) -> "SynthConfig":
        """Inverse of :meth:`to_json`; unknown keys are an InputError."""
        return dataclass_from_json(cls, data, "synth config")
