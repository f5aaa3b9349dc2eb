"""The desktop bundle's entry point (PyInstaller runs this file): the `dolphinfit` command,
with `gui` when started without arguments (a double-click)."""

import sys

from dolphinfit.app.cli import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:] or ["gui"]))
