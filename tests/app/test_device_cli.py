"""--device of the commands that compute with torch: cuda where torch sees no GPU, and names
other than auto, cpu and cuda, are refused with exit 2 naming the option, before any work."""

import pytest
import torch

from dolphinfit.app.cli import main

COMMANDS = {
    "fit": ["fit", "clip.mp4", "--altitude", "20", "--out", "fit"],
    "masks": ["masks", "clip.mp4", "--seed", "10,10", "--out", "masks"],
    "train": ["train", "edges", "--out", "edges.npz"],
    "batch": ["batch", "manifest.csv"],
}


@pytest.mark.parametrize("command", COMMANDS)
def test_cuda_without_a_gpu_exits_2_naming_the_option(command, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(torch.cuda, "is_available", lambda: False)
    assert main([*COMMANDS[command], "--device", "cuda"]) == 2
    err = capsys.readouterr().err
    assert "--device cuda: torch" in err and "sees no CUDA GPU" in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("command", COMMANDS)
def test_other_device_names_exit_2_naming_the_option(command, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exit_:
        main([*COMMANDS[command], "--device", "gpu"])
    assert exit_.value.code == 2
    assert "argument --device: invalid choice: 'gpu'" in capsys.readouterr().err
