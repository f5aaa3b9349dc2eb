"""Foreign bodies: synthetic animals outside the template's family, for a held-out split.

The suite's animals are the template with random part scales, a smooth width/height warp
and other sections: the family the fit's model spans, or nearly. A foreign body differs where
real animals and other artists' meshes differ from ours and the fit cannot follow exactly:

- a width profile of another shape (a stubby or a long, thin beak, a neck behind the melon,
  the widest point further forward or back, a thicker or thinner tail stock), as factors on
  the template's half widths at knots along the body, joined by a monotone cubic (PCHIP), so
  features narrower than the fit's profile field's B-splines stay;
- heights with factors of their own (a keeled tail stock, a flatter or deeper trunk);
- fins of other sizes and planforms: flukes of another span and sweep, larger or smaller
  flippers and dorsal fin.

Only sections change: vertices keep their place along the body, so the rostrum tip, the
notch and the station rings stay where the template has them, and the truth's length and
station extents are measured as for any synthetic animal. Fins first follow the body
vertices under their base (as everywhere), then scale about their base.
"""

from dataclasses import dataclass, replace

import numpy as np
import torch
from scipy.interpolate import PchipInterpolator

from dolphinfit.core.model.profile_field import body_sections, fin_index, follow_bases
from dolphinfit.core.model.template import Template
from dolphinfit.core.synth.config import TEMPLATE_BODY


@dataclass(frozen=True)
class ForeignBody:
    """How one foreign animal differs from the template (factors of 1 change nothing)."""

    shows: str
    width_knots: tuple[tuple[float, float], ...]    # (t, factor on the half width)
    height_knots: tuple[tuple[float, float], ...]   # (t, factor on the half height, over width's)
    fluke_span: float = 1.0       # the flukes' reach from their base, sideways
    fluke_sweep_bl: float = 0.0   # fluke tips set back by this × body length (0 at the base)
    flipper_scale: float = 1.0
    dorsal_scale: float = 1.0


FOREIGN_BODIES: dict[str, ForeignBody] = {
    "robust": ForeignBody(
        "a robust animal: stubby beak, full head and chest, thick tail stock, large flippers",
        width_knots=((0.0, 1.0), (0.03, 1.35), (0.08, 1.15), (0.2, 1.12), (0.35, 1.05),
                     (0.5, 0.98), (0.7, 1.06), (0.85, 1.12), (1.0, 1.0)),
        height_knots=((0.0, 1.0), (0.3, 1.05), (0.6, 1.08), (1.0, 1.0)),
        fluke_span=1.15, flipper_scale=1.25),
    "slender": ForeignBody(
        "a slender animal: long thin beak, narrow trunk widest at 45 %, swept broad flukes",
        width_knots=((0.0, 1.0), (0.02, 0.7), (0.05, 0.72), (0.1, 0.9), (0.25, 0.88),
                     (0.45, 0.95), (0.65, 0.9), (0.85, 0.82), (1.0, 1.0)),
        height_knots=((0.0, 1.0), (0.4, 0.95), (1.0, 1.0)),
        fluke_span=1.3, fluke_sweep_bl=0.03, flipper_scale=0.85),
    "keeled": ForeignBody(
        "a neck behind the melon, a keeled deep tail stock, a tall dorsal fin, small flukes",
        width_knots=((0.0, 1.0), (0.07, 1.05), (0.12, 0.86), (0.18, 1.04), (0.3, 1.02),
                     (0.55, 1.0), (0.75, 0.94), (1.0, 1.0)),
        height_knots=((0.0, 1.0), (0.55, 1.0), (0.7, 1.12), (0.85, 1.18), (1.0, 1.0)),
        fluke_span=0.85, dorsal_scale=1.4),
}


def foreign_template(template: Template, name: str) -> Template:
    """``template`` reshaped into the foreign body ``name`` (module doc); the template
    itself for ``TEMPLATE_BODY``."""
    if name == TEMPLATE_BODY:
        return template
    body = FOREIGN_BODIES[name]
    sections = body_sections(template)
    width = PchipInterpolator(*zip(*body.width_knots))(sections.t)
    height = width * PchipInterpolator(*zip(*body.height_knots))(sections.t)
    moved = template.verts.copy()
    x, y, z = template.verts[sections.body].T
    moved[sections.body, 1] = y * width
    moved[sections.body, 2] = sections.centre_z + (z - sections.centre_z) * height
    rest = torch.as_tensor(template.verts)
    moved = follow_bases(torch.as_tensor(moved), rest, fin_index(template)).numpy()
    for joint, fin in template.fin_vertices.items():
        moved[fin] = _scaled_fin(moved[fin], moved[template.fin_bases[joint]].mean(0),
                                 joint, body, template.length_m)
    return replace(template, verts=moved)


def _scaled_fin(verts: np.ndarray, base: np.ndarray, joint: str, body: ForeignBody,
                length_m: float) -> np.ndarray:
    """A fin's vertices scaled about its base centre as ``body`` says for its kind."""
    offset = verts - base
    if joint.startswith("fluke"):
        reach = np.abs(offset[:, 1])
        offset[:, 1] *= body.fluke_span
        offset[:, 0] -= body.fluke_sweep_bl * length_m * reach / max(reach.max(), 1e-9)
    elif joint.startswith("flipper"):
        offset *= body.flipper_scale
    elif joint.startswith("dorsal"):
        offset *= body.dorsal_scale
    return base + offset
