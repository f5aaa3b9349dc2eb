"""Crash reports: what happened, where, with which versions, after which actions."""

from dolphinfit.core.crash_report import log_dir, versions, write_crash_report


def failing() -> None:
    raise RuntimeError("the renderer's buffer ran out")


def test_a_report_holds_the_traceback_versions_and_last_actions():
    try:
        failing()
    except RuntimeError as exc:
        path = write_crash_report(exc, "the app", ["open", "measure_frame", "fit"])
    assert path.parent == log_dir() and path.name.startswith("crash-")
    text = path.read_text()
    assert "where: the app" in text
    assert "RuntimeError: the renderer's buffer ran out" in text and "in failing" in text
    assert "  measure_frame\n" in text and "last actions (3, oldest first)" in text
    found = versions()
    assert found["dolphinfit"] != "not installed" and f"  torch: {found['torch']}" in text
