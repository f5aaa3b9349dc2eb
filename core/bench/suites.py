"""The widened synthetic suite: clips where what fails on real water fails first. This is
the tuning split, where settings are chosen; ``core.bench.held_out`` holds the split that
nothing is tuned on (``scenarios(split="held-out")``).

Twelve named scenarios at 1920×1080, 3 s, 10 fps (shape SD 0.05, lengths 2.0–2.7 m,
altitudes 15–25 m), each with every effect the fit does not model on (finer mesh, profile
warp, scattering, refraction, ripples, glints, mp4v compression) plus the look of real
footage: light-grey or dark *Tursiops* over green, blue or sandy water, sun glitter, wet
highlights, white water, a second animal, deep murky passes and sharp turns.

Two sets of animals (``SHAPES``): "varied" (the default) gives each animal heights drawn from
the default HW table (its ratios and SDs) and cross-sections from lean to full superellipses
(exponents 1.8–2.2, mean 2: −4.3 % to +3.5 % of volume at the same widths and heights), the
animals a fit meets when someone else built them; "template" keeps the template's heights
and elliptical sections (the suite before, clip for clip). Two frame sizes
(``FRAME_SIZES``): 1080p (the default) and 4K UHD, the same scenes with four times the pixels
(drones record 4K by default; the blur, noise and compression of a pixel stay a pixel's).
Clips are rendered once into the cache (``cache_dir()/<suite>/NAME``) and reused while their
recorded configuration matches.
"""

from dataclasses import replace

from dolphinfit.core.bench.held_out import HELD_OUT
from dolphinfit.core.bench.scenario import Scenario, scenario_maker
from dolphinfit.core.bench.vtk_split import VTK_SPLIT
from dolphinfit.core.limits import one_of
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET
from dolphinfit.core.synth.config import Effects, SynthConfig

VARIED_SUITE_NAME = "bench-suite-v3-shapes"
# held-out: core.bench.held_out, never tuned on; vtk: core.bench.vtk_split, drawn by VTK
SPLITS = ("tuning", "held-out", "vtk")
DEFAULT_SPLIT = "tuning"
SHAPES = ("varied", "template")
DEFAULT_SHAPES = "varied"
FRAME_SIZES = {"1080p": (1920, 1080), "4k": (3840, 2160)}   # name: (width, height) px
DEFAULT_FRAME_SIZE = "1080p"
# one per scenario, in order; mean 2 (the ellipse), so no net bias in volume
SECTION_EXPONENTS = (2.0, 2.15, 1.9, 2.2, 1.95, 2.1, 1.85, 2.05, 2.0, 1.9, 2.1, 1.8)


_BASE = SynthConfig(width_px=1920, height_px=1080, fps=10.0, duration_s=3.0, shape_sd=0.05,
                    colouration="light_grey", glitter=0.25, wet_specular=0.35, splash=0.3,
                    sea_state=0.25, noise_sd=0.012, effects=Effects(finer_mesh=True))


_scenario = scenario_maker(_BASE)


SUITE: tuple[Scenario, ...] = (
    _scenario("grey_green", "green", "light-grey animal over green coastal water (Shark Bay)",
              seed=201, length_m=2.45, altitude_m=19.5, heading_deg=25.0, dive_depth_m=0.3),
    _scenario("grey_green_high", "green", "a small light-grey animal from 25 m, calm sea",
              seed=202, length_m=2.0, altitude_m=25.0, heading_deg=-60.0, sea_state=0.1,
              dive_depth_m=0.2),
    _scenario("grey_blue", "blue", "light-grey animal over clear blue water",
              seed=203, length_m=2.6, altitude_m=18.0, heading_deg=140.0, dive_depth_m=0.5),
    _scenario("dark_sandy", "sandy", "dark animal over sandy shallows with seagrass patches",
              seed=204, colouration="dark", length_m=2.3, altitude_m=15.0, heading_deg=70.0,
              dive_depth_m=0.4),
    _scenario("pair_alongside", "green", "a second animal swimming 1.1 m to the left",
              seed=205, length_m=2.5, altitude_m=20.0, heading_deg=-20.0,
              companion_offset_m=1.1, companion_ahead_m=0.4, companion_length_m=2.3,
              dive_depth_m=0.2),
    _scenario("pair_touching", "green", "a second animal touching the target's right flank",
              seed=206, length_m=2.4, altitude_m=20.0, heading_deg=100.0,
              companion_offset_m=-0.5, companion_ahead_m=-0.6, companion_length_m=2.6,
              dive_depth_m=0.1),
    _scenario("surface_splash", "blue", "surfacing with splash and a white-water wake",
              seed=207, length_m=2.7, altitude_m=17.0, heading_deg=200.0, surface_depth_m=0.02,
              dive_depth_m=0.5, speed_m_s=2.6, splash=1.0, sea_state=0.35),
    _scenario("deep_murky", "murky", "a low-contrast pass a metre down in murky water",
              seed=208, length_m=2.5, altitude_m=22.0, heading_deg=-120.0, surface_depth_m=0.5,
              dive_depth_m=0.7, splash=0.0),
    _scenario("glitter_heavy", "green", "heavy sun glitter over and around the animal",
              seed=209, length_m=2.35, altitude_m=20.0, heading_deg=10.0, glitter=1.0,
              sea_state=0.5, sun_elevation_deg=74.0, sun_azimuth_deg=180.0, dive_depth_m=0.3),
    _scenario("turn_left", "green", "a sharp left turn at 50°/s, the body bending with it",
              seed=210, length_m=2.55, altitude_m=20.0, heading_deg=-30.0, turn_deg_s=50.0,
              turn_flex=1.0, speed_m_s=1.8, dive_depth_m=0.2),
    _scenario("turn_right", "blue", "a sharp right turn at 45°/s over blue water",
              seed=211, length_m=2.2, altitude_m=16.0, heading_deg=60.0, turn_deg_s=-45.0,
              turn_flex=1.0, speed_m_s=1.6, dive_depth_m=0.3),
    _scenario("grey_sandy_pair", "sandy", "light-grey pair over sandy shallows",
              seed=212, length_m=2.15, altitude_m=23.0, heading_deg=-150.0,
              companion_offset_m=-1.4, companion_ahead_m=-0.8, dive_depth_m=0.3),
)


def scenarios(shapes: str = DEFAULT_SHAPES, frame_size: str = DEFAULT_FRAME_SIZE,
              split: str = DEFAULT_SPLIT) -> tuple[Scenario, ...]:
    """The tuning split's scenarios with the animals of ``shapes`` at ``frame_size`` (module
    doc), or the held-out or VTK split's (which have their own animals and frame sizes)."""
    one_of(shapes, SHAPES, "suite shapes")
    one_of(frame_size, tuple(FRAME_SIZES), "suite frame size")
    one_of(split, SPLITS, "suite split")
    if split == "held-out":
        return HELD_OUT
    if split == "vtk":
        return VTK_SPLIT
    chosen = SUITE if shapes == "template" else tuple(
        replace(scenario, suite=VARIED_SUITE_NAME,
                config=replace(scenario.config, hw_table=DEFAULT_PRESET,
                               section_exponent=exponent))
        for scenario, exponent in zip(SUITE, SECTION_EXPONENTS, strict=True))
    if frame_size == DEFAULT_FRAME_SIZE:
        return chosen
    width, height = FRAME_SIZES[frame_size]
    return tuple(replace(scenario, suite=f"{scenario.suite}-{frame_size}",
                         config=replace(scenario.config, width_px=width, height_px=height))
                 for scenario in chosen)
