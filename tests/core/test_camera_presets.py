"""Tests for core/camera_presets.py: bundled and user presets, the config folder, checks."""

import json

import pytest

from dolphinfit.core.camera_presets import (
    CONFIG_DIR_ENV,
    DEFAULT_PRESET,
    CameraPreset,
    config_dir,
    get_preset,
    load_presets,
    preset_resolution_mismatch,
    save_user_preset,
    user_presets_path,
)
from dolphinfit.core.errors import InputError


@pytest.fixture(autouse=True)
def isolated_user_config(tmp_path, monkeypatch):
    """Point the user presets at an empty temporary folder."""
    monkeypatch.setenv(CONFIG_DIR_ENV, str(tmp_path / "config"))


def test_bundled_presets_load_with_paper_default():
    """The bundled file loads; the default is the paper's 5.1K mode, γ = 17.27, ω = 12.29."""
    presets = load_presets()
    default = presets[DEFAULT_PRESET]
    assert (default.sensor_width_mm, default.focal_mm) == (17.27, 12.29)
    assert (default.image_width_px, default.image_height_px) == (5120, 2700)
    assert default.approximate is False
    assert default.intrinsics().focal_px == pytest.approx(12.29 / 17.27 * 5120, rel=1e-12)
    mavic3 = [p for p in presets.values() if p.name.startswith("dji-mavic3-")]
    assert len(mavic3) == 5
    assert sum(p.approximate for p in mavic3) == 4


def test_config_dir_and_user_presets_path_follow_environment(tmp_path, monkeypatch):
    """$DOLPHINFIT_CONFIG_DIR wins; then $XDG_CONFIG_HOME/dolphinfit; then ~/.config/dolphinfit.
    The presets file is cameras.json in that folder."""
    assert config_dir() == tmp_path / "config"
    assert user_presets_path() == tmp_path / "config" / "cameras.json"
    monkeypatch.delenv(CONFIG_DIR_ENV)
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "xdg"))
    assert user_presets_path() == tmp_path / "xdg" / "dolphinfit" / "cameras.json"
    monkeypatch.delenv("XDG_CONFIG_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert config_dir() == tmp_path / "home" / ".config" / "dolphinfit"


def test_user_preset_is_saved_and_overrides_bundled():
    """A saved user preset is found by load_presets and replaces a bundled one of that name."""
    mine = CameraPreset(name="my-drone", description="calibrated", focal_mm=8.8,
                        sensor_width_mm=13.2, image_width_px=3840, image_height_px=2160,
                        source="chessboard calibration 2024-05", approximate=False)
    override = CameraPreset(name=DEFAULT_PRESET, description="re-measured", focal_mm=12.3,
                            sensor_width_mm=17.3, image_width_px=5120, image_height_px=2700,
                            source="my lab", approximate=False)
    path = save_user_preset(mine)
    save_user_preset(override)
    assert path == user_presets_path() and path.exists()
    assert not list(path.parent.glob("*.tmp"))
    presets = load_presets()
    assert presets["my-drone"] == mine
    assert presets[DEFAULT_PRESET].focal_mm == 12.3
    assert presets[DEFAULT_PRESET].source == "my lab"
    assert get_preset("my-drone").intrinsics().focal_px == pytest.approx(2560.0, rel=1e-12)
    assert len(json.loads(path.read_text())["presets"]) == 2


def test_malformed_json_raises_input_error_naming_file(tmp_path):
    """A user file that is not JSON raises InputError naming the file."""
    path = tmp_path / "cameras.json"
    path.write_text("{ not json")
    with pytest.raises(InputError, match="cameras.json.*not valid JSON"):
        load_presets(path)


def test_missing_field_and_bad_value_raise_input_error(tmp_path):
    """A preset without focal_mm, or with a negative width, raises InputError saying so."""
    entry = {"name": "x", "description": "", "focal_mm": 8.8, "sensor_width_mm": 13.2,
             "image_width_px": 3840, "image_height_px": 2160, "source": "", "approximate": True}
    path = tmp_path / "cameras.json"
    path.write_text(json.dumps({"schema_version": 1, "presets": [{**entry, "focal_mm": None}]}))
    with pytest.raises(InputError, match="'focal_mm' has the wrong type"):
        load_presets(path)
    del entry["focal_mm"]
    path.write_text(json.dumps({"schema_version": 1, "presets": [entry]}))
    with pytest.raises(InputError, match=r"missing fields \['focal_mm'\]"):
        load_presets(path)
    path.write_text(json.dumps({"schema_version": 1, "presets": [
        {**entry, "focal_mm": 8.8, "image_width_px": -3840}]}))
    with pytest.raises(InputError, match=r"cameras.json.*'x'.*image_width_px.*-3840"):
        load_presets(path)


def test_unknown_preset_lists_available_names():
    """get_preset with an unknown name raises InputError listing the presets."""
    with pytest.raises(InputError, match=f"no-such-camera.*{DEFAULT_PRESET}"):
        get_preset("no-such-camera")


def test_resolution_mismatch_warns_only_for_another_image_size():
    """The default 5120×2700 preset matches a 5120×2700 clip; a 3840×2160 clip gets a warning
    naming the preset and both sizes."""
    preset = get_preset(DEFAULT_PRESET)
    assert preset_resolution_mismatch(preset, 5120, 2700) is None
    warning = preset_resolution_mismatch(preset, 3840, 2160)
    assert DEFAULT_PRESET in warning and "5120×2700" in warning and "3840×2160" in warning
