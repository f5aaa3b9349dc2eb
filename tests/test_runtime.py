"""torch thread configuration."""

import pytest
import torch

from core.runtime import THREADS_ENV, configure_threads


def test_explicit_thread_count_is_applied():
    """An explicit count is set on torch and returned."""
    try:
        assert configure_threads(2) == 2
        assert torch.get_num_threads() == 2
    finally:
        configure_threads(1)


def test_thread_count_from_environment(monkeypatch):
    """Without an explicit count, the environment variable decides."""
    monkeypatch.setenv(THREADS_ENV, "1")
    assert configure_threads() == 1
    assert torch.get_num_threads() == 1


def test_thread_count_below_one_is_rejected():
    """Zero threads is an error, not a silent default."""
    with pytest.raises(ValueError, match="at least 1"):
        configure_threads(0)
