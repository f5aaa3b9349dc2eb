"""torch thread configuration."""

import pytest
import torch

from dolphinfit.core.errors import InputError
from dolphinfit.core.runtime import THREADS_ENV, configure_threads


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
    with pytest.raises(InputError, match="at least 1"):
        configure_threads(0)


@pytest.mark.parametrize("text", ["0", "-3", "two", "1.5", ""])
def test_bad_thread_count_in_the_environment_names_the_variable(monkeypatch, text):
    """A count below one or not a whole number in the variable is an error naming it."""
    monkeypatch.setenv(THREADS_ENV, text)
    with pytest.raises(InputError, match=rf"\${THREADS_ENV}"):
        configure_threads()
