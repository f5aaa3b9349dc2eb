"""Template sections with other heights or shapes than the built template's.

A top view sees widths; the heights and the fullness of each cross-section it cannot see. The
template's heights are one guess (morphometrics.md §4, the lower end of its HW ranges); an HW
table is another (``core.measure.hw_ratios``: the elliptical baseline's, with its
provenance). ``reshape_sections`` gives the template the heights of given HW ratios at the
5–85 % stations (the ratios relax to the template's behind 85 %, where no table has data) and,
optionally, superellipse sections of exponent n (2 is the ellipse; its area at the same width
and height is 4·Γ(1 + 1/n)² / Γ(1 + 2/n) / π of the ellipse's). Used by the fit (its hidden
heights from the user's HW table) and by the synthetic animals (heights and sections unlike
the template's).

Body vertices move within their section (about the template's section centre); each fin
moves with the mean displacement of the body vertices its base stands on, so it stays
attached, unstretched.
"""

import math
from dataclasses import replace

import numpy as np
import torch
from scipy.interpolate import PchipInterpolator

from dolphinfit.core.measure.elliptical import TAIL_IDX
from dolphinfit.core.measure.stations import STATION_FRACTIONS
from dolphinfit.core.model.profile import height_fraction, width_fraction
from dolphinfit.core.model.profile_field import body_sections, fin_index, follow_bases
from dolphinfit.core.model.template import Template

NUM_TABLE_STATIONS = TAIL_IDX[0]   # 5–85 %: HW tables have no data at the flukes' 90, 95 %
TAIL_BLEND_T = 0.92   # behind the 85 % station the heights relax to the template's by here
MIN_HALF_WIDTH_BL = 1e-4  # the apexes (zero width) stay where they are

def section_area_factor(exponent: float) -> float:
    """Area of a superellipse of ``exponent`` over the ellipse's with the same axes."""
    return 4.0 * math.gamma(1.0 + 1.0 / exponent) ** 2 / math.gamma(1.0 + 2.0 / exponent) / math.pi


def height_factor(station_hw: np.ndarray):
    """k(t): the factor on the template's half height at fraction ``t`` of body length that
    gives the animal the HW ratios ``station_hw`` at 5–85 %; 1 at the rostrum tip and from
    ``TAIL_BLEND_T`` to the notch."""
    stations = STATION_FRACTIONS[:NUM_TABLE_STATIONS]
    knots_t = np.concatenate([[0.0], stations, [TAIL_BLEND_T, 1.0]])
    template_hw = height_fraction(stations) / width_fraction(stations)
    knots_k = np.concatenate([[1.0], station_hw / template_hw, [1.0, 1.0]])
    return PchipInterpolator(knots_t, knots_k)


def reshape_sections(template: Template, station_hw: np.ndarray | None,
                     exponent: float = 2.0) -> Template:
    """The template with its heights following ``station_hw`` (None: the template's) and its
    sections superellipses of ``exponent`` (module doc)."""
    sections = body_sections(template)
    _, y, z = template.verts[sections.body].T
    inside = sections.half_width > MIN_HALF_WIDTH_BL * template.length_m
    u = np.where(inside, y / np.where(inside, sections.half_width, 1.0), 0.0)
    v = np.where(inside, (z - sections.centre_z) / np.where(inside, sections.half_height, 1.0),
                 0.0)
    radius, angle = np.hypot(u, v), np.arctan2(u, v)
    power = 2.0 / exponent
    u_new = radius * np.sign(np.sin(angle)) * np.abs(np.sin(angle)) ** power
    v_new = radius * np.sign(np.cos(angle)) * np.abs(np.cos(angle)) ** power
    k = (np.ones_like(sections.t) if station_hw is None
         else height_factor(station_hw)(sections.t))
    moved = template.verts.copy()
    moved[sections.body, 1] = np.where(inside, sections.half_width * u_new, y)
    moved[sections.body, 2] = np.where(
        inside, sections.centre_z + k * sections.half_height * v_new, z)
    rest = torch.as_tensor(template.verts)
    moved = follow_bases(torch.as_tensor(moved), rest, fin_index(template))
    return replace(template, verts=moved.numpy())
