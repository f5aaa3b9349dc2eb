"""HW ratio tables: the bundled presets, user CSVs, and ratios from the 3D model."""

import numpy as np
import pytest
import torch

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.hw_ratios import (
    FROM_MODEL, load_hw_preset, preset_names, read_hw_csv, write_hw_csv,
)
from dolphinfit.core.measure.mesh import station_profile
from dolphinfit.core.model.hw_from_model import hw_from_template
from dolphinfit.core.model.hw_spec import resolve_hw
from dolphinfit.core.model.template import load_template


def test_provisional_preset_is_the_reference_prior():
    """tursiops-provisional: §4 band midpoints, SD = range / 4, no data at 90/95 %."""
    hw = load_hw_preset("tursiops-provisional")
    assert hw.is_provisional and "morphometrics.md §4" in hw.source
    np.testing.assert_allclose(hw.ratios[:17], np.repeat([1.0, 1.125, 1.4, 1.625, 2.4],
                                                         [3, 5, 3, 4, 2]))
    assert hw.sd[3] == pytest.approx((1.2 - 1.05) / 4) and hw.sd[16] == pytest.approx(0.2)
    assert np.isnan(hw.ratios[17:]).all() and hw.carries_tail_ratio
    ratios, sd = hw.completed()
    assert ratios[17] == ratios[18] == 2.4 and sd[18] == pytest.approx(0.2)


def test_bundled_presets_are_listed_and_circular_is_exact():
    """Both bundled tables load; circular has HW = 1 everywhere and no uncertainty."""
    assert {"circular", "tursiops-provisional"} <= set(preset_names())
    circular = resolve_hw("circular")
    assert not circular.is_provisional and not circular.carries_tail_ratio
    np.testing.assert_array_equal(circular.ratios, 1.0)
    np.testing.assert_array_equal(circular.sd, 0.0)


def _write_csv(path, rows, header="# name: mine\n# source: lateral images, 2025\n"):
    path.write_text(header + "station_pct,hw_ratio,hw_ratio_sd\n" + rows, encoding="utf-8")
    return path


def test_user_csv_is_read_with_its_provenance(tmp_path):
    """A user table keeps its name and source; the SD column may be left empty."""
    rows = "".join(f"{p},{1 + p / 100:.2f},\n" for p in range(5, 100, 5))
    hw = read_hw_csv(_write_csv(tmp_path / "mine.csv", rows))
    assert (hw.name, hw.source, hw.is_provisional) == ("mine", "lateral images, 2025", False)
    assert hw.ratios[9] == pytest.approx(1.5) and not hw.sd.any()
    assert resolve_hw(str(tmp_path / "mine.csv")).ratios[0] == pytest.approx(1.05)


@pytest.mark.parametrize("rows, message", [
    ("5,1.0,0\n5,1.1,0\n", "line 5: station_pct '5'"),
    ("7,1.0,0\n", "line 4: station_pct '7'"),
    ("5,one,0\n", "line 4: hw_ratio 'one' is not a number"),
    ("5,-1,0\n", "line 4: hw_ratio must be positive"),
    ("5,1.0,0\n", "no HW ratio for the stations 10 %"),
])
def test_bad_user_csv_names_file_and_line(tmp_path, rows, message):
    """Repeated or unknown stations, bad numbers and missing stations raise InputError."""
    path = _write_csv(tmp_path / "bad.csv", rows)
    with pytest.raises(InputError, match=message) as info:
        read_hw_csv(path)
    assert str(path) in str(info.value)


def test_unknown_preset_and_missing_file_are_input_errors(tmp_path):
    """An unknown name lists the presets; a missing .csv names the file."""
    with pytest.raises(InputError, match="available: circular"):
        resolve_hw("orca")
    with pytest.raises(InputError, match="not found"):
        resolve_hw(str(tmp_path / "missing.csv"))


def test_ratios_from_the_model_are_its_station_heights_over_widths():
    """--hw model: the template's height / width per station ring (1.0 on the head, > 1.4 on
    the tail stock), labelled provisional like the template's profile."""
    template = load_template()
    hw = resolve_hw(FROM_MODEL)
    profile = station_profile(torch.as_tensor(template.verts),
                              torch.as_tensor(template.station_rings))
    np.testing.assert_allclose(hw.ratios, (profile.height / profile.width).numpy(), rtol=1e-12)
    np.testing.assert_allclose(hw.ratios[:3], 1.0, atol=1e-3)
    assert hw.ratios[15:17].min() > 1.4 and hw.is_provisional
    assert hw_from_template(template).name == FROM_MODEL


def test_written_tables_read_back_with_their_provenance(tmp_path):
    table = hw_from_template()
    path = tmp_path / "fit_hw.csv"
    write_hw_csv(path, table)
    back = read_hw_csv(path)
    np.testing.assert_array_equal(back.ratios, table.ratios)
    np.testing.assert_array_equal(back.sd, table.sd)
    assert (back.name, back.source, back.is_provisional) == (table.name, table.source,
                                                              table.is_provisional)
