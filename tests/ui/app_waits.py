"""What the app's tests and the long-session script wait for."""

import numpy as np

from dolphinfit.core.measure.annotation import pixel_measurements


def results_caught_up(window) -> bool:
    """Whether the results panel shows the current measured frame's pixels (its Monte Carlo
    interval included)."""
    wanted = pixel_measurements(window.model.current_measurement().to_annotation())
    result = window.results.current_result()
    return (result is not None and result.estimate.interval is not None
            and result.estimate.measured.length_px == wanted.length_px
            and np.array_equal(result.estimate.measured.widths_px, wanted.widths_px,
                               equal_nan=True))
