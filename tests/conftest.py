"""Test-wide settings: one torch thread (stable on 2 cores, reference/platform.md §8), and
crash reports and config kept out of the user's folders."""

import pytest

from dolphinfit.core.runtime import configure_threads

configure_threads(1)


@pytest.fixture(autouse=True)
def crash_reports_in_tmp(tmp_path_factory, monkeypatch):
    """Every test's crash reports go to a folder of its own run."""
    monkeypatch.setenv("DOLPHINFIT_LOG_DIR", str(tmp_path_factory.mktemp("log")))


@pytest.fixture(autouse=True)
def user_config_in_tmp(tmp_path_factory, monkeypatch):
    """No test reads or writes the user's config folder (camera presets, the lens models
    kept with them, recent projects, preferences)."""
    monkeypatch.setenv("DOLPHINFIT_CONFIG_DIR", str(tmp_path_factory.mktemp("config")))
