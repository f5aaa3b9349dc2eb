"""Body condition and mass: the paper's model against hand-computed values."""

import numpy as np
import pytest

from dolphinfit.core.measure.condition import MassModel, body_condition, expected_volume

# reference/morphometrics.md §3.1: BL (m), BV_exp (m³), BM (kg) at BCI = −0.2, 0, +0.2
TABLE = [(2.0, 0.1082, 91, 108, 123), (2.2, 0.1386, 117, 139, 157),
         (2.4, 0.1737, 147, 174, 197), (2.5, 0.1931, 163, 193, 219),
         (2.6, 0.2137, 181, 214, 242), (2.7, 0.2357, 199, 236, 267),
         (2.78, 0.2542, 215, 254, 288), (3.01, 0.3124, 264, 313, 354)]


def test_bci_zero_gives_mass_1000_71_times_volume():
    """At BV = BV_exp, BCI = 0, density = α and BM = 1000.71·BV."""
    volume = expected_volume(2.5)
    result = body_condition(2.5, volume)
    assert float(result.bci) == pytest.approx(0.0, abs=1e-15)
    assert float(result.mass_kg) == pytest.approx(1000.71 * volume, rel=1e-15)


def test_hand_computed_case():
    """BL 2.5 m, BV 0.231 m³: BV_exp 0.193061, BCI 0.196514, BD 946.056, BM 218.539 kg."""
    result = body_condition(2.5, 0.231)
    assert float(result.expected_volume_m3) == pytest.approx(0.193061, abs=1e-6)
    assert float(result.bci) == pytest.approx(0.196514, abs=1e-6)
    assert float(result.density_kg_m3) == pytest.approx(946.056, abs=1e-3)
    assert float(result.mass_kg) == pytest.approx(218.539, abs=1e-3)
    assert not bool(result.is_outside_fit_range)


@pytest.mark.parametrize("length_m, bv_exp, light, mean, heavy", TABLE)
def test_reference_table(length_m, bv_exp, light, mean, heavy):
    """BV_exp to 4 decimals and BM at BCI −0.2, 0, +0.2 to the kilogram (§3.1)."""
    assert float(expected_volume(length_m)) == pytest.approx(bv_exp, abs=5e-5)
    volumes = expected_volume(length_m) * np.array([0.8, 1.0, 1.2])
    masses = body_condition(np.full(3, length_m), volumes).mass_kg
    np.testing.assert_allclose(masses, [light, mean, heavy], atol=0.5)


def test_density_at_the_ends_of_the_trusted_range():
    """Density 1084 kg/m³ at BCI −0.3 and 917 kg/m³ at +0.3 (§3.1)."""
    volumes = expected_volume(2.5) * np.array([0.7, 1.3])
    density = body_condition(2.5, volumes).density_kg_m3
    np.testing.assert_allclose(density, [1084.146, 917.274], atol=1e-3)


def test_bci_outside_the_fit_range_is_flagged_and_configurable():
    """BCI ±0.35 is flagged under the provisional ±0.3, not under a ±0.4 range."""
    volumes = expected_volume(2.5) * np.array([0.65, 1.0, 1.35])
    flags = body_condition(2.5, volumes).is_outside_fit_range
    assert flags.tolist() == [True, False, True]
    wide = MassModel(bci_fit_range=(-0.4, 0.4))
    assert not body_condition(2.5, volumes, wide).is_outside_fit_range.any()
    with pytest.raises(ValueError, match="low < high"):
        MassModel(bci_fit_range=(0.3, -0.3))
