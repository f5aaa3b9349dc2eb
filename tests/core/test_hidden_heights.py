"""The hidden-height floor of a synthetic clip: what a top view must miss of its volume."""

import pytest

from dolphinfit.core.bench.hidden_heights import hidden_height_floor, truth_sections
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.model.sections import section_area_factor
from dolphinfit.core.synth.config import Effects, SynthConfig

PLAIN = SynthConfig(seed=4, shape_sd=0.0, effects=Effects(profile_warp=False))
TEMPLATE_FIT = FitConfig(hw_table=None)   # the template's own heights


def test_a_template_animal_has_no_floor_for_a_template_fit():
    assert hidden_height_floor(truth_sections(PLAIN), TEMPLATE_FIT) == pytest.approx(
        0.0, abs=1e-9)


def test_the_floor_is_the_hidden_heights_and_sections_of_the_truth():
    """A fit that takes the HW table's heights overestimates a template-shaped animal by
    8–13 % (the table's ratios are larger); fuller truth sections lower the floor by their
    area factor; an animal with the table's heights has no floor for that fit."""
    table_fit = FitConfig()   # the default: the default HW table's heights
    over = hidden_height_floor(truth_sections(PLAIN), table_fit)
    assert 0.08 < over < 0.13
    full = SynthConfig(seed=4, shape_sd=0.0, effects=Effects(profile_warp=False),
                       section_exponent=2.3)
    assert hidden_height_floor(truth_sections(full), TEMPLATE_FIT) == pytest.approx(
        1.0 / section_area_factor(2.3) - 1.0, abs=5e-4)   # widths move by the faceting
    # table heights drawn with the table's SD: within a few SDs of none
    drawn = SynthConfig(seed=4, shape_sd=0.0, effects=Effects(profile_warp=False),
                        hw_table="tursiops-provisional")
    assert abs(hidden_height_floor(truth_sections(drawn), table_fit)) < 0.08
