"""Tests for `dolphinfit camera` (app/commands/camera.py) through app.cli.main."""

import json

import pytest

from dolphinfit.app.cli import main
from dolphinfit.core.camera_presets import CONFIG_DIR_ENV, DEFAULT_PRESET, load_presets


@pytest.fixture(autouse=True)
def isolated_user_config(tmp_path, monkeypatch):
    """Point the user presets at an empty temporary folder."""
    monkeypatch.setenv(CONFIG_DIR_ENV, str(tmp_path))


def test_list_json_contains_default(capsys):
    """`camera list --json` prints JSON naming the default with its derived values."""
    assert main(["camera", "list", "--json"]) == 0
    listing = json.loads(capsys.readouterr().out)
    assert listing["default"] == DEFAULT_PRESET
    default = next(p for p in listing["presets"] if p["name"] == DEFAULT_PRESET)
    assert (default["sensor_width_mm"], default["focal_mm"]) == (17.27, 12.29)
    assert default["fov_x_deg"] == pytest.approx(70.2, abs=0.05)
    assert default["gsd_m_per_px"] == pytest.approx(20 / (12.29 / 17.27 * 5120), rel=1e-12)


def test_list_table_shows_default(capsys):
    """`camera list` prints a table with the default, its field of view and GSD at 20 m."""
    assert main(["camera", "list"]) == 0
    line = next(row for row in capsys.readouterr().out.splitlines()
                if row.startswith(DEFAULT_PRESET))
    assert "5120x2700" in line and "70.2°" in line and "0.55 cm/px" in line


def test_add_then_show(capsys, tmp_path):
    """`camera add` saves a user preset that `camera show` then describes at 30 m."""
    assert main(["camera", "add", "my-drone", "--sensor-width-mm", "13.2", "--focal-mm", "8.8",
                 "--width-px", "3840", "--height-px", "2160", "--description", "test rig"]) == 0
    assert "added camera preset 'my-drone'" in capsys.readouterr().out
    assert (tmp_path / "cameras.json").exists()
    assert load_presets()["my-drone"].approximate is False

    assert main(["camera", "show", "my-drone", "--altitude-m", "30"]) == 0
    out = capsys.readouterr().out
    # f = 8.8 / 13.2 × 3840 = 2560 px; GSD = 30 / 2560 m = 1.171875 cm/px
    assert "2560.00 px" in out
    assert "1.172 cm/px" in out
    assert "45.00 x 25.31 m" in out


def test_add_approximate_overrides_bundled(capsys):
    """`camera add --approximate` on a bundled name replaces it and keeps the flag."""
    assert main(["camera", "add", DEFAULT_PRESET, "--sensor-width-mm", "17.3", "--focal-mm",
                 "12.3", "--width-px", "5120", "--height-px", "2700", "--approximate"]) == 0
    assert "replaced" in capsys.readouterr().out
    preset = load_presets()[DEFAULT_PRESET]
    assert (preset.focal_mm, preset.approximate) == (12.3, True)


def test_add_rejects_non_positive_focal(capsys):
    """A negative --focal-mm exits with 2 and names the option."""
    assert main(["camera", "add", "bad", "--sensor-width-mm", "13.2", "--focal-mm", "-8.8",
                 "--width-px", "3840", "--height-px", "2160"]) == 2
    assert "--focal-mm: -8.8 mm is outside the plausible range 1–1000 mm" in \
        capsys.readouterr().err


def test_show_unknown_camera_lists_names(capsys):
    """`camera show no-such-camera` exits with 2 and lists the available presets."""
    assert main(["camera", "show", "no-such-camera"]) == 2
    err = capsys.readouterr().err
    assert "no-such-camera" in err and DEFAULT_PRESET in err


def test_show_rejects_non_positive_altitude(capsys):
    """`camera show --altitude-m 0` exits with 2 naming the option."""
    assert main(["camera", "show", DEFAULT_PRESET, "--altitude-m", "0"]) == 2
    assert "--altitude-m" in capsys.readouterr().err
