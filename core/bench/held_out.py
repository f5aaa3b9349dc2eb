"""The held-out split: synthetic clips nothing in dolphinfit was tuned or trained on.

The tuning split (``core.bench.suites``) is where fit settings, mask thresholds and the edge
network's training scenes were chosen; figures measured there flatter us. These eight clips
share none of its choices that a tuning step could have learnt:

- foreign bodies (``core.synth.foreign``): width profiles, beaks, heights and fins outside
  the template's family;
- two waters the tuning split never shows (``turquoise`` over white sand with caustics,
  dark ``ocean``), and foam wash along the flanks of a surfacing animal;
- two clips rendered at 5K (5120×2880) and delivered at 720p, as a downscaled field video:
  animals 8–15 px wide;
- H.264 at drone and delivery bit rates (the tuning split is mp4v).

Clips are 3 s at 10 fps, as in the tuning split, with heights drawn from the default HW table
and superellipse sections. Do not change a setting because of a figure measured here: report
it apart, and judge a change on the tuning split first.
"""

from dolphinfit.core.bench.scenario import Scenario, scenario_maker
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET
from dolphinfit.core.synth.config import Effects, SynthConfig

HELD_OUT_SUITE = "bench-held-out-v1"
DELIVERY_MBPS = 8.0      # a 720p clip as delivered from a downscaled 5K original
DRONE_MBPS = 25.0        # 1080p as a drone records it

_BASE = SynthConfig(width_px=1920, height_px=1080, fps=10.0, duration_s=3.0, shape_sd=0.05,
                    colouration="light_grey", glitter=0.2, wet_specular=0.3, splash=0.25,
                    sea_state=0.3, noise_sd=0.012, hw_table=DEFAULT_PRESET, codec="h264",
                    bitrate_mbps=DRONE_MBPS, effects=Effects(finer_mesh=True))
_FIVE_K_AT_720P = dict(width_px=1280, height_px=720, supersample=4, bitrate_mbps=DELIVERY_MBPS)


_scenario = scenario_maker(_BASE, HELD_OUT_SUITE)


HELD_OUT: tuple[Scenario, ...] = (
    _scenario("robust_turquoise", "turquoise", "a robust animal over turquoise water and sand",
              seed=401, body="robust", length_m=2.5, altitude_m=18.0, heading_deg=35.0,
              section_exponent=2.1, dive_depth_m=0.3),
    _scenario("slender_ocean", "ocean", "a dark slender animal over deep ocean water",
              seed=402, body="slender", colouration="dark", length_m=2.3, altitude_m=20.0,
              heading_deg=-75.0, section_exponent=1.9, dive_depth_m=0.4),
    _scenario("keeled_foam", "green", "a keeled animal surfacing in a foam wash",
              seed=403, body="keeled", length_m=2.6, altitude_m=17.0, heading_deg=160.0,
              surface_depth_m=0.02, splash=1.0, speed_m_s=2.4, dive_depth_m=0.4,
              section_exponent=2.0),
    _scenario("robust_foam_turn", "blue", "a dark robust animal turning through foam",
              seed=404, body="robust", colouration="dark", length_m=2.2, altitude_m=16.0,
              heading_deg=-140.0, surface_depth_m=0.03, splash=0.9, turn_deg_s=35.0,
              turn_flex=1.0, section_exponent=2.15, dive_depth_m=0.3),
    _scenario("small_5k_pair", "green", "5K at 720p from 30 m, 12 px wide, a second animal",
              seed=405, body="slender", length_m=2.4, altitude_m=30.0, heading_deg=10.0,
              companion_offset_m=1.2, companion_ahead_m=0.3, companion_length_m=2.2,
              section_exponent=1.95, dive_depth_m=0.3, **_FIVE_K_AT_720P),
    _scenario("small_5k_turquoise", "turquoise", "5K at 720p from 42 m, 10 px wide",
              seed=406, body="robust", length_m=2.6, altitude_m=42.0, heading_deg=-30.0,
              section_exponent=2.05, dive_depth_m=0.3, **_FIVE_K_AT_720P),
    _scenario("keeled_ocean_turn", "ocean", "a keeled animal in a sharp turn offshore",
              seed=407, body="keeled", length_m=2.4, altitude_m=22.0, heading_deg=80.0,
              turn_deg_s=-45.0, turn_flex=1.0, speed_m_s=1.7, section_exponent=1.85,
              dive_depth_m=0.3),
    _scenario("slender_pair_touching", "sandy", "a slender animal with another at its flank",
              seed=408, body="slender", colouration="dark", length_m=2.7, altitude_m=21.0,
              heading_deg=120.0, companion_offset_m=-0.55, companion_ahead_m=-0.5,
              companion_length_m=2.5, section_exponent=2.2, dive_depth_m=0.2),
)
