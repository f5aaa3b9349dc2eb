"""What the comparison panel and the 3D viewer show of both methods (the app computes it off the
GUI thread): the rows of core.project.comparison, the fitted model's station widths and heights
beside the measured and HW-ratio ones, and the elliptical model as a solid."""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.fit.result import FitResult
from dolphinfit.core.measure.baseline import BaselineEstimate
from dolphinfit.core.measure.elliptical_solid import elliptical_solid
from dolphinfit.core.project.comparison import ComparisonRow, compare


@dataclass(frozen=True, eq=False)
class ComparisonView:
    """Rows for the table, (S,) profiles in metres for the plot, the elliptical solid."""

    rows: list[ComparisonRow]
    measured_widths_m: np.ndarray
    used_widths_m: np.ndarray
    hw_heights_m: np.ndarray
    fitted_widths_m: np.ndarray
    fitted_heights_m: np.ndarray
    solid_verts: np.ndarray
    solid_faces: np.ndarray


def comparison_view(estimate: BaselineEstimate, fit: FitResult,
                    frame_width_px: int) -> ComparisonView:
    """Both methods of one animal in a clip ``frame_width_px`` wide (loads torch for the
    fitted profile: worker only)."""
    from dolphinfit.core.model.hw_from_model import station_extents
    from dolphinfit.core.model.template import load_template

    fitted_widths, fitted_heights = station_extents(fit.rest_verts,
                                                    load_template().station_rings)
    point = estimate.point
    verts, faces = elliptical_solid(float(point.length_m), point.widths_m, point.heights_m)
    return ComparisonView(rows=compare(estimate, fit, frame_width_px),
                          measured_widths_m=estimate.measured.widths_px * estimate.m_per_px,
                          used_widths_m=point.widths_m,
                          hw_heights_m=point.heights_m, fitted_widths_m=fitted_widths,
                          fitted_heights_m=fitted_heights, solid_verts=verts, solid_faces=faces)
