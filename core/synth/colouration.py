"""The synthetic animal's colours: the template's dark albedo or a light-grey *Tursiops*.

The light-grey pattern follows descriptions of bottlenose dolphins as light to slate grey: a
darker grey cape along the back from the rostrum to behind the dorsal fin, fading on the tail
stock, lighter grey flanks, a pale belly, and darker dorsal fin, flippers and flukes. Seen from
a drone the cape is a darker stripe down a pale grey body. A faint blue cast makes it the
bluish grey of wet skin in daylight.
"""

import numpy as np

from dolphinfit.core.model.template import Template
from dolphinfit.core.model.texture import Countershading, build_albedo

LIGHT_GREY = Countershading(
    cape=0.42, flank=0.64, belly=0.84, cape_edge_shift_deg=-22.0, cape_fade_t=0.62,
    fins={"dorsal_fin": (0.32, 0.32), "flipper": (0.38, 0.60), "fluke": (0.32, 0.66)})
LIGHT_GREY_TINT = np.array([0.96, 1.0, 1.04])


def albedo(template: Template, colouration: str) -> np.ndarray:
    """(512, 512) grayscale or (512, 512, 3) RGB albedo in [0, 1] for ``colouration``."""
    if colouration == "light_grey":
        grey = build_albedo(template.albedo.shape[0], LIGHT_GREY) / 255.0
        return np.clip(grey[..., None] * LIGHT_GREY_TINT, 0.0, 1.0)
    return template.albedo / 255.0
