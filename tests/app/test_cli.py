"""The command line's registry: one-line help as each module says it, lazy imports."""

import subprocess
import sys

import pytest

from dolphinfit.app.cli import SUBCOMMANDS, build_parser, command_module, main


@pytest.mark.parametrize("name", sorted(SUBCOMMANDS))
def test_one_line_help_is_the_modules_first_docstring_line(name):
    doc = (command_module(name).__doc__ or "").strip().splitlines()[0]
    assert SUBCOMMANDS[name] == doc


def test_full_help_lists_every_command(capsys):
    with pytest.raises(SystemExit) as exit_info:
        build_parser().parse_args(["--help"])
    assert exit_info.value.code == 0
    out = capsys.readouterr().out
    assert all(name in out for name in SUBCOMMANDS)


def test_version_names_the_installed_release(capsys):
    from importlib.metadata import version

    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.strip() == f"dolphinfit {version('dolphinfit')}"


def test_gui_help_loads_no_torch():
    probe = ("import sys, contextlib, io\nfrom dolphinfit.app.cli import main\n"
             "with contextlib.redirect_stdout(io.StringIO()):\n"
             "    try:\n        main(['gui', '--help'])\n    except SystemExit:\n        pass\n"
             "print('torch' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout.split()
    assert out == ["False"]


def test_bad_thread_count_is_an_input_error(capsys):
    assert main(["--threads", "0", "camera", "list"]) == 2
    assert "--threads" in capsys.readouterr().err


def test_ctrl_c_stops_at_once_with_exit_130_and_no_traceback():
    """A real SIGINT to a command at work: at once (long before the work's 600 s would end:
    within a tenth of them, the margin a loaded machine's interpreter teardown needs, a few
    seconds on an idle one) it says it was interrupted and what is kept, exits 130 as
    shells expect, and prints no traceback."""
    import signal
    import time

    work_s = 600
    script = ("import sys, time\n"
              "import dolphinfit.app.commands.camera as camera\n"
              "def work(args):\n"
              "    print('working', flush=True)\n"
              f"    time.sleep({work_s})\n"
              "camera.run = work\n"
              "from dolphinfit.app.cli import main\n"
              "sys.exit(main(['camera', 'list']))\n")
    process = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    assert process.stdout.readline().strip() == "working"
    sent = time.monotonic()
    process.send_signal(signal.SIGINT)
    try:
        _, err = process.communicate(timeout=work_s / 10)
    finally:
        process.kill()   # only if it is still at work: the test has failed then
    assert time.monotonic() - sent < work_s / 10
    assert process.returncode == 130
    assert "dolphinfit camera: interrupted" in err and "half-written" in err
    assert "Traceback" not in err


def test_an_internal_error_exits_1_with_a_crash_report_not_a_traceback(capsys, monkeypatch):
    """A fault of ours (not bad input): exit 1, one message naming the crash report, which
    holds the traceback and the command."""
    from dolphinfit.core.crash_report import log_dir

    def broken(args):
        raise ZeroDivisionError("division by zero in the camera table")

    monkeypatch.setattr(command_module("camera"), "run", broken)
    assert main(["camera", "list"]) == 1
    err = capsys.readouterr().err
    assert "internal error: division by zero in the camera table" in err
    assert "Traceback" not in err
    (report,) = log_dir().glob("crash-*.txt")
    assert str(report) in err
    text = report.read_text()
    assert "where: dolphinfit camera" in text and "ZeroDivisionError" in text
