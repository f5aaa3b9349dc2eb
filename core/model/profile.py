"""Body profile of the procedural template: widths, heights and ring angles along the body.

Positions along the body are fractions ``t`` of body length BL measured from the rostrum tip
(t = 0) to the fluke notch (t = 1). Widths are lateral extents and heights dorso-ventral
extents, fins excluded, both as fractions of BL.

Sources (reference/morphometrics.md): the width table of §4 (provisional, from artist meshes)
scaled by ``WIDTH_SCALE`` and the HW trend of §4/§6 (round head, laterally compressed tail
stock), tuned so the closed template's volume / BL³ is about 0.013, inside the 0.011–0.015
band the paper's data allow (§3.1: BV_exp / BL³ = 0.0122 at 2.6 m).
"""

import numpy as np
from scipy.interpolate import PchipInterpolator

from dolphinfit.core.measure.stations import STATION_FRACTIONS

# Width / BL at t (morphometrics.md §4 table, with a rounded rostrum tip and a tail cone
# towards the notch added here).
_WIDTH_T = (0.0, 0.002, 0.006, 0.015, 0.035, 0.05, 0.07, 0.10, 0.15, 0.20, 0.25, 0.30, 0.35, 0.40,
            0.45, 0.50, 0.55, 0.60, 0.65, 0.70, 0.75, 0.80, 0.85, 0.90, 0.95, 0.98, 1.0)
_WIDTH_V = (0.0, 0.009, 0.014, 0.020, 0.027, 0.045, 0.068, 0.085, 0.13, 0.15, 0.165, 0.175, 0.18, 0.18,
            0.175, 0.16, 0.14, 0.125, 0.11, 0.09, 0.075, 0.06, 0.045, 0.030, 0.018, 0.010, 0.0)
# The §4 table gives V/BL³ ≈ 0.0145 with fins; 0.97 brings it to ≈ 0.013 (see module doc).
WIDTH_SCALE = 0.97

# Height / width at t: ≈ 1 on the head, rising over the tail stock (morphometrics.md §4 prior,
# lower end of its ranges), relaxing to round where the body meets the flukes.
_HW_T = (0.0, 0.05, 0.10, 0.15, 0.20, 0.30, 0.40, 0.50, 0.60, 0.70, 0.80, 0.85, 0.90, 0.95, 1.0)
_HW_V = (1.0, 1.0, 1.0, 1.0, 1.02, 1.05, 1.08, 1.18, 1.35, 1.6, 1.9, 2.1, 1.7, 1.2, 1.0)

# Vertical offset of the section centre as a fraction of its half height: the melon rises
# above the beak, whose tip stays on the body axis (so BL is the straight tip-to-notch line).
_LIFT_T = (0.0, 0.03, 0.06, 0.12, 0.20, 0.30, 1.0)
_LIFT_V = (0.0, 0.15, 0.30, 0.28, 0.12, 0.0, 0.0)

_width = PchipInterpolator(_WIDTH_T, np.asarray(_WIDTH_V) * WIDTH_SCALE)
_hw = PchipInterpolator(_HW_T, _HW_V)
_lift = PchipInterpolator(_LIFT_T, _LIFT_V)

# Ring positions (fractions of BL). Every 1/80 BL between 5 % and 95 % so that each
# station is a ring; finer near the rounded rostrum tip and the tail cone.
_TIP_ROWS = (0.002, 0.006, 0.012, 0.02, 0.03, 0.04)
_TAIL_ROWS = (0.9625, 0.975, 0.985, 0.992, 0.997)


def width_fraction(t: np.ndarray) -> np.ndarray:
    """Body width / BL at fractions ``t`` (fins excluded)."""
    return _width(np.asarray(t, dtype=np.float64))


def height_fraction(t: np.ndarray) -> np.ndarray:
    """Body height / BL at fractions ``t`` (fins excluded)."""
    t = np.asarray(t, dtype=np.float64)
    return _width(t) * _hw(t)


def centre_lift_fraction(t: np.ndarray) -> np.ndarray:
    """Height of the section centre above the body axis / BL at fractions ``t``."""
    return 0.5 * height_fraction(t) * _lift(np.asarray(t, dtype=np.float64))


def ring_fractions() -> np.ndarray:
    """(NR,) float64 body-ring positions in (0, 1), stations included exactly."""
    middle = np.arange(4, 77) / 80.0
    return np.concatenate([_TIP_ROWS, middle, _TAIL_ROWS])


def station_rows(rows_t: np.ndarray) -> np.ndarray:
    """(19,) int64 indices of the rings lying at the 19 stations."""
    idx = np.array([int(np.argmin(np.abs(rows_t - s))) for s in STATION_FRACTIONS])
    if not np.allclose(rows_t[idx], STATION_FRACTIONS, atol=1e-12):
        raise ValueError("ring positions do not include every station")
    return idx
