"""The desktop app: measure length and widths by hand, see volume, BCI and mass at once.

  dolphinfit gui [PROJECT | CLIP | IMAGE | FOLDER]
  dolphinfit gui --sample [--screenshot PNG | --quit-when-shown]

Opens a project (.dolphinfit), or media: a video, a still image (JPG, PNG, TIFF, DNG preview)
or a folder of numbered frames; media without a project starts one beside it (autosaved).
--sample opens the bundled sample project; its clip is rendered into the cache on first use,
like the demo's. --screenshot measures the sample dolphin from its mask, saves a picture of
the window to PNG and exits (the README's screenshot); --quit-when-shown quits as soon as the
first frame is on screen (`dolphinfit bench app` times that). Needs a display (on a server, run it
under xvfb-run); `dolphinfit demo` is the headless job.
"""

import argparse
import os
import sys
from pathlib import Path

from dolphinfit.core.errors import InputError

# torch is imported at start (ui/app.py), but the work that computes with it sets its threads.
LOADS_TORCH = False


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The path to open, --sample and --screenshot."""
    parser.add_argument("path", type=Path, nargs="?", default=None,
                        help="project, clip, image or folder of frames to open")
    parser.add_argument("--sample", action="store_true",
                        help="open the bundled sample project (rendered on first use)")
    parser.add_argument("--screenshot", type=Path, default=None, metavar="PNG",
                        help="with --sample: measure the sample, save the window to PNG, exit")
    parser.add_argument("--quit-when-shown", action="store_true",
                        help="quit once the first frame is on screen (start-up timing)")


def _check_display() -> None:
    """InputError, not a Qt abort, when a Linux session has no screen to show the window on."""
    if sys.platform.startswith("linux") and not any(
            os.environ.get(name) for name in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM")):
        raise InputError("no display to open the app on: run it in a desktop session, or "
                         "under xvfb-run for a screenshot; `dolphinfit demo` is the headless "
                         "job")


def run(args: argparse.Namespace) -> int:
    """Open the app."""
    _check_display()
    if args.path is not None and args.sample:
        raise InputError("give a path or --sample, not both")
    if args.screenshot is not None and not args.sample:
        raise InputError("--screenshot works with --sample")
    if args.path is not None and not args.path.exists():
        raise InputError(f"{args.path}: no such file or folder")
    path = args.path
    if args.sample:
        from dolphinfit.core.project.sample import ensure_sample_project
        print("sample clip: rendering on first use, then cached")
        path = ensure_sample_project()
    if args.screenshot is not None:
        from dolphinfit.app.screenshot import save_screenshot
        return save_screenshot(path, args.screenshot)
    return run_app(path, quit_when_shown=args.quit_when_shown)


def run_app(path: Path | None = None, quit_when_shown: bool = False) -> int:
    """Show the main window (opening ``path`` if given) and run the event loop, with the
    crash handler (ui/crash_handler.py) installed.

    ``quit_when_shown``: quit once the first frame is on screen (start-up timing).
    """
    from dolphinfit.ui.app import application
    from dolphinfit.ui.crash_handler import CrashHandler
    from dolphinfit.ui.main_window import MainWindow
    app = application()
    window = MainWindow()
    if quit_when_shown:
        window.state.frame_shown.connect(lambda _: app.quit())
    if window.layout_restored:
        window.show()
    else:
        window.showMaximized()  # the first start: the video as large as the screen allows
    if path is not None:
        window.files.open_path(path)
    crashes = CrashHandler(window.model, window.recent_actions, window.ask.crash)
    crashes.install()
    try:
        return app.exec()
    finally:
        crashes.uninstall()
