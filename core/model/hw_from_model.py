"""HW ratios measured on a dolphin mesh: the template's, or a fitted animal's.

Apart from core/measure/hw_ratios.py because it needs the mesh stack (torch), which the
preset and CSV tables, and so the app's elliptical measurements, never load.
"""

import numpy as np
import torch

from dolphinfit.core.measure.hw_ratios import FROM_MODEL, HWRatios
from dolphinfit.core.measure.mesh import station_profile
from dolphinfit.core.model.template import Template, load_template


def station_extents(verts: np.ndarray, rings: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(S,) widths and (S,) heights of a body mesh at its station rings, metres (fins
    excluded), e.g. a fitted animal's rest mesh beside the widths measured on the image.

    verts: (V, 3) float metres; rings: (S, R) int64 station rings (see
    core.measure.mesh.station_profile).
    """
    profile = station_profile(torch.as_tensor(verts, dtype=torch.float64),
                              torch.as_tensor(rings))
    return profile.width.numpy(), profile.height.numpy()


def hw_from_mesh(verts: np.ndarray, rings: np.ndarray, name: str, source: str,
                 is_provisional: bool) -> HWRatios:
    """HW ratios of a body mesh at its station rings (fins excluded), with no stated SD."""
    widths, heights = station_extents(verts, rings)
    ratios = heights / widths
    return HWRatios(name=name, ratios=ratios, sd=np.zeros_like(ratios), source=source,
                    is_provisional=is_provisional)


def hw_from_template(template: Template | None = None) -> HWRatios:
    """HW ratios of the procedural template's rest mesh (the bundled one by default).

    Provisional: the template's profile follows the provisional trends of
    reference/morphometrics.md §4. A fitted mesh goes through :func:`hw_from_mesh`.
    """
    template = load_template() if template is None else template
    return hw_from_mesh(template.verts, template.station_rings, name=FROM_MODEL,
                        source="station heights / widths of the dolphinfit template mesh "
                               "(core/model, built from the provisional trends of "
                               "reference/morphometrics.md §4)", is_provisional=True)
