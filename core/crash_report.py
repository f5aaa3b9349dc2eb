"""Crash reports: what a user sends when dolphinfit fails on its own account (an internal
error, not bad input). One text file per crash in the log folder: when and where it
happened, the versions of Python, the platform and the packages that matter, the last actions
taken (their names only) and the traceback. Nothing of the user's data goes in beyond the
file names a message or traceback already holds.

The log folder is ``$DOLPHINFIT_LOG_DIR``, else the platform's log folder for dolphinfit
(platformdirs: ``~/.local/state/dolphinfit/log`` on Linux). ``FAULTS_FILE`` there takes
faulthandler's dump of a hard crash (a segmentation fault in a native library), which no
Python handler sees.
"""

import datetime
import os
import platform
import traceback
from collections.abc import Sequence
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import platformdirs

LOG_DIR_ENV = "DOLPHINFIT_LOG_DIR"
FAULTS_FILE = "faults.log"
PACKAGES = ("dolphinfit", "torch", "numpy", "scipy", "opencv-contrib-python-headless",
            "PySide6-Essentials", "pyvista", "vtk", "trimesh", "dask", "av")


def log_dir() -> Path:
    """The folder crash reports and the fault log go to (module doc), made if missing."""
    folder = Path(os.environ.get(LOG_DIR_ENV) or platformdirs.user_log_dir("dolphinfit"))
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def installed_version(package: str) -> str | None:
    """The installed distribution's version; None where it is not installed."""
    try:
        return version(package)
    except PackageNotFoundError:
        return None


def versions() -> dict[str, str]:
    """Python's, the platform's and each of ``PACKAGES``' version ("not installed")."""
    found = {"python": platform.python_version(), "platform": platform.platform()}
    return found | {name: installed_version(name) or "not installed" for name in PACKAGES}


def report_text(error: BaseException, where: str, recent_actions: Sequence[str]) -> str:
    """The report of ``error`` raised in ``where`` (a command, or "the app")."""
    lines = [f"dolphinfit crash report, {datetime.datetime.now().isoformat(timespec='seconds')}",
             f"where: {where}", "", "versions:"]
    lines += [f"  {name}: {value}" for name, value in versions().items()]
    lines += ["", f"last actions ({len(recent_actions)}, oldest first):"]
    lines += [f"  {name}" for name in recent_actions] or ["  (none recorded)"]
    lines += ["", "traceback:", *"".join(traceback.format_exception(error)).rstrip().split("\n")]
    return "\n".join(lines) + "\n"


def write_crash_report(error: BaseException, where: str,
                       recent_actions: Sequence[str] = ()) -> Path:
    """Write the report of ``error`` (module doc) to a new file in ``log_dir``; its path."""
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    path = log_dir() / f"crash-{stamp}-{os.getpid()}.txt"
    path.write_text(report_text(error, where, recent_actions), encoding="utf-8")
    return path


def open_fault_log():
    """The fault log opened for appending, for ``faulthandler.enable(file=…)``; the caller
    closes it."""
    return open(log_dir() / FAULTS_FILE, "a", encoding="utf-8")  # noqa: SIM115

