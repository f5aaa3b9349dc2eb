"""Named water presets: the colour, clarity and seabed of a few kinds of real water.

Colours are what a drone camera records of deep water (display values in [0, 1]); clarity is
the per-channel attenuation in 1/m. ``green`` is coastal water over seagrass as in Shark Bay
(green, moderately clear: light-grey dolphins stand out pale); ``blue`` is clear oceanic
water; ``sandy`` is clear shallow water over a patchy sand and seagrass bed 2.5 m down;
``murky`` is turbid, low-contrast water where an animal half a metre down nearly vanishes.
Two more only the held-out split uses (``core.bench.held_out``), so nothing is tuned on them:
``turquoise``, bright water over white sand 4 m down, where a light-grey animal is darker
than its background; and ``ocean``, deep, dark navy offshore water.
"""

from dataclasses import replace

from dolphinfit.core.errors import InputError
from dolphinfit.core.synth.config import SynthConfig

WATER_PRESETS: dict[str, dict] = {
    "green": dict(water_rgb=(0.16, 0.33, 0.26), clarity_per_m=(0.50, 0.20, 0.32),
                  seabed_depth_m=None, seabed_cover=0.0),
    "blue": dict(water_rgb=(0.05, 0.23, 0.41), clarity_per_m=(0.45, 0.12, 0.07),
                 seabed_depth_m=None, seabed_cover=0.0),
    "sandy": dict(water_rgb=(0.10, 0.30, 0.34), clarity_per_m=(0.20, 0.11, 0.11),
                  seabed_depth_m=2.5, seabed_rgb=(0.58, 0.54, 0.44), seabed_cover=0.35),
    "murky": dict(water_rgb=(0.13, 0.27, 0.24), clarity_per_m=(1.10, 0.70, 0.80),
                  seabed_depth_m=None, seabed_cover=0.0),
    "turquoise": dict(water_rgb=(0.12, 0.45, 0.50), clarity_per_m=(0.35, 0.08, 0.07),
                      seabed_depth_m=4.0, seabed_rgb=(0.85, 0.82, 0.72), seabed_cover=0.05),
    "ocean": dict(water_rgb=(0.02, 0.09, 0.20), clarity_per_m=(0.50, 0.12, 0.06),
                  seabed_depth_m=None, seabed_cover=0.0),
}


def with_water(config: SynthConfig, name: str) -> SynthConfig:
    """``config`` with the water fields of preset ``name``."""
    if name not in WATER_PRESETS:
        raise InputError(f"water preset {name!r}: one of {', '.join(WATER_PRESETS)}")
    return replace(config, **WATER_PRESETS[name])
