"""`dolphinfit train edges`: its options checked before anything is rendered or trained (the
recipe itself is tested in tests/core/segment/test_edge_net.py)."""

import pytest

from dolphinfit.app.cli import main


@pytest.mark.parametrize("args, problem", [
    (["--out", "weights.pt"], "--out weights.pt: the weights are written as .npz"),
    (["--out", "w.npz", "--clips", "3"], "--clips: must be at least 10, got 3"),
    (["--out", "w.npz", "--hard-clips", "-1"], "--hard-clips: must be at least 0, got -1"),
    (["--out", "w.npz", "--steps", "0"], "--steps: must be at least 1, got 0"),
    (["--out", "w.npz", "--workers", "0"], "--workers: must be at least 1, got 0"),
])
def test_bad_options_exit_2_naming_the_option(args, problem, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["train", "edges", *args]) == 2
    assert problem in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_an_out_that_is_a_folder_is_refused(tmp_path, capsys):
    folder = tmp_path / "weights.npz"
    folder.mkdir()
    assert main(["train", "edges", "--out", str(folder)]) == 2
    assert f"--out {folder}: is a folder" in capsys.readouterr().err


def test_only_the_edge_network_can_be_trained(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["train", "salient", "--out", "w.npz"])
    assert exit_.value.code == 2
    assert "invalid choice: 'salient'" in capsys.readouterr().err
