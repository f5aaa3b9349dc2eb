"""The project's exception for bad user input (files, values, options).

The CLI maps :class:`InputError` to exit code 2 (DESIGN.md §8); every other exception is an
internal error (exit code 1).
"""


class InputError(Exception):
    """Bad input: the message names the file (or option), where, and what is wrong."""
