"""Body condition and mass from body volume and length: the paper's mass model.

Baieri et al. (arXiv 2504.15782, §Mass Estimation; reference/morphometrics.md §3), following
Christiansen et al. 2018 for the body condition index:

    BV_exp = exp(a + b·ln BL)             expected volume, m³ (BL in m)
    BCI    = (BV − BV_exp) / BV_exp
    BD     = α − β·BCI                    density, kg/m³
    BM     = BV·BD                        mass, kg

Plain numpy, broadcasting over any batch shape ``...``. The relation was fitted on dolphins
under human care over a BCI range the paper does not state; results outside a provisional
±0.3 are flagged (morphometrics.md §3).
"""

from dataclasses import dataclass

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.limits import BCI, DENSITY_KG_M3, check_fields, in_range

# The paper's mass-model figure gives four decimals (its text rounds to −4.02 and 2.59).
BV_EXP_INTERCEPT = -4.0206  # a, ln m³: ln BV_exp at BL = 1 m (Baieri et al., mass-model figure)
BV_EXP_SLOPE = 2.5929       # b: allometric exponent of volume on length (same figure)
DENSITY_INTERCEPT_KG_M3 = 1000.71  # α: density at BCI = 0 (Baieri et al., eq. BD = α − β·BCI)
DENSITY_SLOPE_KG_M3 = 278.12       # β: density drop per unit BCI (same equation)
BCI_FIT_RANGE = (-0.3, 0.3)  # provisional: the fitted range is unstated (morphometrics.md §3)


@dataclass(frozen=True)
class MassModel:
    """Constants of the volume → BCI → density → mass chain (defaults: the paper's).

    ``bci_fit_range``: (low, high) BCI range the relation is trusted on; results outside are
    flagged.
    """

    bv_exp_intercept: float = BV_EXP_INTERCEPT
    bv_exp_slope: float = BV_EXP_SLOPE
    density_intercept_kg_m3: float = DENSITY_INTERCEPT_KG_M3
    density_slope_kg_m3: float = DENSITY_SLOPE_KG_M3
    bci_fit_range: tuple[float, float] = BCI_FIT_RANGE

    def __post_init__(self) -> None:
        check_fields(self, "mass model ")
        if len(self.bci_fit_range) != 2:
            raise InputError(f"mass model bci_fit_range: expected (low, high), got "
                             f"{self.bci_fit_range!r}")
        low, high = (in_range(v, BCI, "mass model bci_fit_range") for v in self.bci_fit_range)
        for bci in (low, high):  # the density the model gives over its trusted range
            in_range(self.density_intercept_kg_m3 - self.density_slope_kg_m3 * bci,
                     DENSITY_KG_M3, f"mass model density at BCI {bci:+g}")
        if not low < high:
            raise ValueError(f"bci_fit_range must be (low, high) with low < high, "
                             f"got {self.bci_fit_range!r}")


@dataclass(frozen=True, eq=False)
class BodyCondition:
    """Body condition and mass; each field (...) like the inputs."""

    expected_volume_m3: np.ndarray
    bci: np.ndarray
    density_kg_m3: np.ndarray
    mass_kg: np.ndarray
    is_outside_fit_range: np.ndarray  # bool: BCI outside the model's bci_fit_range


def expected_volume(length_m: np.ndarray, model: MassModel = MassModel()) -> np.ndarray:
    """(...) BV_exp = exp(a + b·ln BL), m³, for body lengths (...) in metres."""
    return np.exp(model.bv_exp_intercept + model.bv_exp_slope * np.log(length_m))


def body_condition(length_m: np.ndarray, volume_m3: np.ndarray,
                   model: MassModel = MassModel()) -> BodyCondition:
    """BCI, density and mass from body length (...) m and body volume (...) m³."""
    expected = expected_volume(length_m, model)
    bci = (np.asarray(volume_m3) - expected) / expected
    density = model.density_intercept_kg_m3 - model.density_slope_kg_m3 * bci
    low, high = model.bci_fit_range
    return BodyCondition(
        expected_volume_m3=expected,
        bci=bci,
        density_kg_m3=density,
        mass_kg=np.asarray(volume_m3) * density,
        is_outside_fit_range=(bci < low) | (bci > high),
    )
