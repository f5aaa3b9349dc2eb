"""Test-wide settings: one torch thread (stable on 2 cores, reference/platform.md §8)."""

from core.runtime import configure_threads

configure_threads(1)
