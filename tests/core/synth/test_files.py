"""Whether a cached synthetic clip was made from a configuration."""

import json
from dataclasses import replace

import pytest

from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import TRUTH_SCHEMA_VERSION, clip_files, made_from

CONFIG = SynthConfig(seed=3, width_px=320, height_px=240)


def _cached(tmp_path, recorded: dict):
    files = clip_files(tmp_path, CONFIG)
    files.video.write_bytes(b"video")
    files.parts.write_bytes(b"parts")
    files.truth_json.write_text(json.dumps({"schema_version": TRUTH_SCHEMA_VERSION,
                                            "config": recorded}))
    return files


def test_a_clip_made_before_new_options_is_still_current(tmp_path):
    """A truth written before hw_table and section_exponent existed (their defaults render
    as before) matches today's configuration; another option value does not."""
    recorded = CONFIG.to_json()
    del recorded["hw_table"], recorded["section_exponent"]
    files = _cached(tmp_path, recorded)
    assert made_from(files, CONFIG)
    assert not made_from(files, replace(CONFIG, seed=4))
    assert not made_from(files, replace(CONFIG, hw_table="tursiops-provisional"))


def test_unreadable_or_foreign_truths_are_stale(tmp_path):
    files = _cached(tmp_path, {**CONFIG.to_json(), "from_the_future": 1})
    assert not made_from(files, CONFIG)
    files.truth_json.write_text("{not json")
    assert not made_from(files, CONFIG)
    files.truth_json.write_text(json.dumps({"schema_version": TRUTH_SCHEMA_VERSION,
                                            "config": CONFIG.to_json()}))
    assert made_from(files, CONFIG)
    files.truth_json.write_text(json.dumps({"config": CONFIG.to_json()}))
    assert not made_from(files, CONFIG)      # true masks by the rules before schema 2
    files.truth_json.write_text(json.dumps({"schema_version": TRUTH_SCHEMA_VERSION,
                                            "config": CONFIG.to_json()}))
    files.parts.unlink()     # a clip cut short before its part masks
    assert not made_from(files, CONFIG)
    files.truth_json.unlink()
    assert not made_from(files, CONFIG)


def test_a_cache_folder_under_a_file_is_an_input_error_naming_it(tmp_path):
    """`dolphinfit demo` with its cache under a file said NotADirectoryError in a traceback."""
    from dolphinfit.core.errors import InputError
    from dolphinfit.core.synth.sample import CACHE_DIR_ENV, SAMPLE_CONFIG, ensure_clip

    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    with pytest.raises(InputError, match=f"a_file/sample: the cache folder cannot be made "
                                         f".*set {CACHE_DIR_ENV}"):
        ensure_clip(SAMPLE_CONFIG, blocker / "sample")
