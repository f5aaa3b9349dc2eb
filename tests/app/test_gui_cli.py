"""``dolphinfit gui`` refuses bad input with exit code 2 before any window opens."""

from dolphinfit.app.cli import main


def test_missing_path_and_bad_option_mix_exit_2(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("DISPLAY", ":99")
    assert main(["gui", str(tmp_path / "nope.mp4")]) == 2
    assert "nope.mp4: no such file or folder" in capsys.readouterr().err
    assert main(["gui", "--screenshot", str(tmp_path / "x.png")]) == 2
    assert "--screenshot works with --sample" in capsys.readouterr().err
    assert main(["gui", str(tmp_path), "--sample"]) == 2


def test_no_display_says_so_instead_of_aborting(monkeypatch, capsys):
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"):
        monkeypatch.delenv(name, raising=False)
    assert main(["gui"]) == 2
    assert "no display" in capsys.readouterr().err
