"""The VTK split: synthetic clips drawn by a renderer that is not dolphinfit's.

The tuning and held-out splits are drawn by ``core.synth``; the networks learnt outlines from
its blur, anti-aliasing and shading, so a figure measured only there flatters them. These
eight clips are drawn by VTK's OpenGL rasterizer (``dolphinfit.vtk_clips``: multisampled,
Phong-shaded vertex colours, water as translucent layers), with the held-out split's foreign
bodies re-posed, at the drone's H.264 bit rates. Never tune on them: they are reported beside
the other two splits, the way a field day someone else made would be.

What a field day brings that the others lack: a calm clean clip with a sharp animal, dark
over dark and light over light, a dive to 1.2 m in a rough sea, 4K delivered at 720p.
"""

from dolphinfit.core.bench.scenario import Scenario, scenario_maker
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET
from dolphinfit.core.synth.config import Effects, SynthConfig

VTK_RENDERER = "vtk"
VTK_SUITE = "bench-vtk-v1"
_BASE = SynthConfig(width_px=1920, height_px=1080, fps=10.0, duration_s=3.0, shape_sd=0.05,
                    colouration="light_grey", glitter=0.1, sea_state=0.2, noise_sd=0.01,
                    blur_px=0.5, hw_table=DEFAULT_PRESET, codec="h264", bitrate_mbps=25.0,
                    effects=Effects(finer_mesh=True))
_FOUR_K_AT_720P = dict(width_px=1280, height_px=720, supersample=3, bitrate_mbps=8.0)


_scenario = scenario_maker(_BASE, VTK_SUITE, VTK_RENDERER)


VTK_SPLIT: tuple[Scenario, ...] = (
    _scenario("calm_clean", "blue", "a sharp light-grey animal alone in a glassy sea",
              seed=601, body="slender", length_m=2.5, altitude_m=20.0, heading_deg=15.0,
              sea_state=0.0, glitter=0.0, blur_px=0.4, section_exponent=2.0,
              dive_depth_m=0.2),
    _scenario("dark_over_dark", "ocean", "a dark animal over dark offshore water",
              seed=602, body="robust", colouration="dark", length_m=2.4, altitude_m=18.0,
              heading_deg=-50.0, section_exponent=2.1, dive_depth_m=0.3),
    _scenario("light_over_light", "turquoise", "a light-grey animal over bright shallows",
              seed=603, body="keeled", length_m=2.3, altitude_m=22.0, heading_deg=100.0,
              section_exponent=1.9, dive_depth_m=0.3),
    _scenario("deep_dive_rough", "green", "a dive to 1.2 m in a rough sea with glitter",
              seed=604, body="robust", length_m=2.5, altitude_m=20.0, heading_deg=200.0,
              surface_depth_m=0.2, dive_depth_m=1.0, sea_state=0.7, glitter=0.6,
              section_exponent=2.05),
    _scenario("pair_side_by_side", "green", "two animals a body's width apart",
              seed=605, body="slender", length_m=2.6, altitude_m=21.0, heading_deg=-120.0,
              companion_offset_m=0.9, companion_ahead_m=0.2, companion_length_m=2.3,
              section_exponent=1.95, dive_depth_m=0.2),
    _scenario("small_4k_720p", "blue", "4K delivered at 720p from 28 m, 11 px wide",
              seed=606, body="keeled", length_m=2.4, altitude_m=28.0, heading_deg=60.0,
              section_exponent=2.0, dive_depth_m=0.3, **_FOUR_K_AT_720P),
    _scenario("turn_glitter", "blue", "a sharp turn under sun glitter",
              seed=607, body="robust", length_m=2.2, altitude_m=16.0, heading_deg=-20.0,
              turn_deg_s=-45.0, turn_flex=1.0, speed_m_s=1.7, glitter=0.8, sea_state=0.4,
              section_exponent=2.15, dive_depth_m=0.3),
    _scenario("dark_sandy_shallows", "sandy", "a dark animal over sand and seagrass",
              seed=608, body="slender", colouration="dark", length_m=2.7, altitude_m=24.0,
              heading_deg=140.0, section_exponent=2.2, dive_depth_m=0.25),
)
