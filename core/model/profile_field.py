"""A smooth field along the body that widens or narrows, deepens or flattens its sections.

Per-part scaling (β) changes a part's width as one piece, and the root part alone spans 25–55 %
of body length, where most of the volume lies: a width profile that bends within a part
(as real animals' and the synthetic suite's do) is out of its reach, and the fit traded width
between neighbouring parts instead. The field adds ``NUM_KNOTS`` clamped cubic B-splines along
the body, applied to the template in its rest frame before the parts scale and pose:

- row 0: the log factor on each body vertex's distance from the midline plane (its section's
  half width);
- row 1: the log factor on its height above or below the section centre, over row 0's (so at
  zero the heights follow the widths and the template's height/width ratios stay).

Fins are moved by the mean displacement of the body vertices their base stands on, not
stretched. At zero the field is the identity; the B-splines sum to one, so a constant row is
a uniform factor.
"""

from dataclasses import dataclass

import numpy as np
import torch
from scipy.interpolate import BSpline

from dolphinfit.core.model.profile import centre_lift_fraction, height_fraction, width_fraction
from dolphinfit.core.model.template import Template

NUM_KNOTS = 10
DEGREE = 3


@dataclass(frozen=True)
class BodySections:
    """Where each body vertex (fins excluded) sits in the template's sections."""

    body: np.ndarray          # (B,) int64 vertex indices of the body
    t: np.ndarray             # (B,) position along the body, fraction of length from the tip
    half_width: np.ndarray    # (B,) the template's half width there, metres
    half_height: np.ndarray   # (B,) the template's half height there, metres
    centre_z: np.ndarray      # (B,) height of the section centre there, metres


def body_sections(template: Template) -> BodySections:
    """The body vertices of ``template`` and their sections (the template's profile)."""
    length = template.length_m
    fins = np.concatenate(list(template.fin_vertices.values()))
    body = np.setdiff1d(np.arange(len(template.verts)), fins)
    t = np.clip((template.verts[template.rostrum_idx, 0] - template.verts[body, 0]) / length,
                0.0, 1.0)
    return BodySections(body=body, t=t, half_width=0.5 * width_fraction(t) * length,
                        half_height=0.5 * height_fraction(t) * length,
                        centre_z=centre_lift_fraction(t) * length)


FinIndex = list[tuple[torch.Tensor, torch.Tensor]]


def fin_index(template: Template) -> FinIndex:
    """(fin vertices, base vertices) index pairs, one per fin."""
    return [(torch.as_tensor(fin), torch.as_tensor(template.fin_bases[joint]))
            for joint, fin in template.fin_vertices.items()]


def follow_bases(moved: torch.Tensor, rest: torch.Tensor, fins: FinIndex) -> torch.Tensor:
    """``moved`` (V, 3) with each fin's vertices at their rest place plus the mean
    displacement of the body vertices under the fin's base."""
    shift = moved - rest
    for fin, base in fins:
        moved = moved.index_copy(0, fin, rest[fin] + shift[base].mean(0))
    return moved


def spline_basis(t: np.ndarray) -> np.ndarray:
    """(len(t), NUM_KNOTS) clamped cubic B-splines on [0, 1] at ``t``; rows sum to one."""
    interior = np.linspace(0.0, 1.0, NUM_KNOTS - DEGREE + 1)
    knots = np.concatenate([[0.0] * DEGREE, interior, [1.0] * DEGREE])
    return BSpline.design_matrix(np.clip(t, 0.0, 1.0), knots, DEGREE).toarray()


class ProfileField(torch.nn.Module):
    """The field of a template (module doc) as buffers; call it with the (2, K) coefficients."""

    def __init__(self, template: Template, dtype: torch.dtype = torch.float32):
        super().__init__()
        fins = fin_index(template)
        self.num_fins = len(fins)
        for k, (fin, base) in enumerate(fins):   # buffers, so that .to(device) moves them
            self.register_buffer(f"fin_{k}", fin)
            self.register_buffer(f"fin_base_{k}", base)
        sections = body_sections(template)
        self.register_buffer("body", torch.as_tensor(sections.body))
        self.register_buffer("basis", torch.tensor(spline_basis(sections.t), dtype=dtype))
        self.register_buffer("centre_z", torch.tensor(sections.centre_z, dtype=dtype))

    @property
    def fins(self) -> FinIndex:
        """(fin vertices, base vertices) index pairs, one per fin (``fin_index``)."""
        return [(self.get_buffer(f"fin_{k}"), self.get_buffer(f"fin_base_{k}"))
                for k in range(self.num_fins)]

    def forward(self, rest_verts: torch.Tensor, coefficients: torch.Tensor) -> torch.Tensor:
        """(V, 3) rest vertices reshaped by ``coefficients`` (2, K)."""
        if coefficients.shape != (2, NUM_KNOTS):
            raise ValueError(f"profile coefficients must be (2, {NUM_KNOTS}); "
                             f"got {tuple(coefficients.shape)}")
        log_width = self.basis @ coefficients[0]
        log_height = log_width + self.basis @ coefficients[1]
        x, y, z = rest_verts[self.body].unbind(-1)
        body = torch.stack([x, y * torch.exp(log_width),
                            self.centre_z + (z - self.centre_z) * torch.exp(log_height)], -1)
        moved = rest_verts.index_copy(0, self.body, body)
        return follow_bases(moved, rest_verts, self.fins)
