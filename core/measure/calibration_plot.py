"""The altitude calibration drawn: each shot's implied against its recorded altitude, the
fitted line, the identity a perfect altimeter would follow, and the shots named as outliers.

Drawn on a matplotlib ``Axes`` so the app's canvas and the command line's PNG show the same."""

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from dolphinfit.core.measure.altitude_calibration import AltitudeCalibration


def draw_altitude_calibration(axes, shots: Sequence, calibration: AltitudeCalibration) -> None:
    """Shots, line and identity on ``axes`` (a matplotlib Axes). ``shots``: each with an
    ``image``, a ``recorded_altitude_m`` and a ``pixel_length`` (a table's or a project's)."""
    recorded = np.array([shot.recorded_altitude_m for shot in shots])
    implied = (calibration.object_length_m * calibration.camera.focal_px
               / np.array([shot.pixel_length for shot in shots]))
    outlying = np.array([shot.image in calibration.outliers for shot in shots])
    axes.scatter(recorded[~outlying], implied[~outlying], s=12, color="#1f77b4",
                 label=f"{(~outlying).sum()} shots")
    if outlying.any():
        axes.scatter(recorded[outlying], implied[outlying], s=30, marker="x", color="#d62728",
                     label=f"{outlying.sum()} beyond 3 SD")
    span = np.array(calibration.recorded_range_m)
    axes.plot(span, calibration.true_altitude(span), color="black",
              label=f"{calibration.intercept_m:+.2f} m + {calibration.slope:.4f} × recorded")
    axes.plot(span, span, color="grey", linestyle="--", label="recorded = true")
    axes.set_xlabel(f"recorded altitude ({calibration.altimeter}), m")
    axes.set_ylabel(f"altitude from the {calibration.object_length_m:g} m object, m")
    axes.set_title(f"spread {100 * calibration.residual_sd_fraction:.2f} % of the altitude",
                   fontsize="medium")
    axes.legend(loc="lower right", fontsize="small")
    axes.grid(True, alpha=0.3)


def save_altitude_calibration_plot(shots: Sequence, calibration: AltitudeCalibration,
                                   path: Path) -> None:
    """The drawing of ``shots`` (as ``draw_altitude_calibration`` takes them) as a PNG at
    ``path``."""
    from matplotlib.figure import Figure

    from dolphinfit.core.io.atomic import atomic_path

    figure = Figure(figsize=(7, 5), dpi=110, layout="tight")
    draw_altitude_calibration(figure.add_subplot(), shots, calibration)
    with atomic_path(Path(path)) as tmp:
        figure.savefig(tmp, format="png")
