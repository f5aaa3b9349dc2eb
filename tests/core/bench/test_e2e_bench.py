"""``dolphinfit bench e2e``'s plumbing: the stage clock, the chains' child processes and the
command line's checks (the chain itself is a full fit: run by the bench, not here)."""

import pytest
import torch

from dolphinfit.app.cli import main
from dolphinfit.core.bench import e2e_bench
from dolphinfit.core.bench.e2e_bench import PACKAGE_ROOT, StageClock, chain_in_child, clip_of
from dolphinfit.core.progress import Progress


def test_the_stage_clock_times_each_stage_from_its_first_report(monkeypatch):
    """Opening lasts until the first report; a stage lasts until the next one's first
    report; one entered twice is summed; the stages add up to the whole."""
    clock = [100.0]
    monkeypatch.setattr(e2e_bench.time, "perf_counter", lambda: clock[0])
    stage_clock = StageClock()
    clock[0] += 0.02
    for stage, pause in (("scan", 0.03), ("scan", 0.01), ("track", 0.02), ("scan", 0.01)):
        stage_clock(Progress(stage, 1, 2))
        clock[0] += pause
    stage_clock.mark("intervals")
    clock[0] += 0.01
    stages = stage_clock.seconds()
    assert list(stages) == ["open", "scan", "track", "intervals"]
    assert stages == pytest.approx({"open": 0.02, "scan": 0.05, "track": 0.02,
                                    "intervals": 0.01})
    assert sum(stages.values()) == pytest.approx(clock[0] - stage_clock.start)


def test_the_4k_clip_is_the_speed_clips_scene():
    assert (clip_of("4k").width_px, clip_of("4k").height_px) == (3840, 2160)
    assert clip_of("1080p").seed == clip_of("4k").seed


def test_the_baseline_runs_the_checkouts_own_engine(tmp_path):
    """The child imports the checkout's package before the installed one: a checkout whose
    runtime module stops at once is the one that ran, and its error is reported."""
    (tmp_path / "core").mkdir()
    (tmp_path / "core" / "runtime.py").write_text(
        "def configure_threads(n):\n    raise SystemExit('the baseline checkout ran')\n")
    with pytest.raises(RuntimeError, match="exited 1: the baseline checkout ran"):
        chain_in_child(tmp_path, "1080p")


def test_every_chain_runs_in_a_fresh_process_this_ones_too(tmp_path, monkeypatch):
    """Before and after start alike: the current engine's chain runs in a child process of
    its own, as the baseline's does, frame size by frame size beside it (in the bench's own
    process the 4K chain ran about 8 % faster after the 1080p one)."""
    calls = []
    monkeypatch.setattr(e2e_bench, "chain_in_child", lambda checkout, size, device: calls.append(
        (checkout, size)) or {"frame_size": size})
    figures = e2e_bench.bench_e2e(("1080p", "4k"), baseline=tmp_path)
    assert calls == [(tmp_path, "1080p"), (PACKAGE_ROOT, "1080p"), (tmp_path, "4k"),
                     (PACKAGE_ROOT, "4k")]
    assert [run["frame_size"] for run in figures["runs"]] == ["1080p", "4k"]
    assert (PACKAGE_ROOT / "core" / "bench" / "e2e_bench.py").is_file()


@pytest.mark.parametrize("args, message", [
    (["--frame-sizes", "1080p,8k"], "--frame-sizes: one of 1080p, 4k, got '8k'"),
    (["--baseline", "{tmp}"], "--baseline {tmp}: not a checkout of dolphinfit"),
])
def test_bad_options_exit_2_naming_them(args, message, tmp_path, capsys):
    args = [a.format(tmp=tmp_path) for a in args]
    assert main(["bench", "e2e", *args]) == 2
    assert message.format(tmp=tmp_path) in capsys.readouterr().err


@pytest.mark.skipif(torch.cuda.is_available(), reason="a CUDA GPU is present")
def test_cuda_without_a_gpu_is_refused_before_any_work(capsys):
    assert main(["bench", "e2e", "--device", "cuda"]) == 2
    assert "--device cuda: torch" in capsys.readouterr().err


def test_a_baseline_is_named_by_its_commit_not_its_path(tmp_path):
    """A kept run names its baseline by what git says it is; a folder git knows nothing of
    by its name, never by a path of one machine."""
    from pathlib import Path

    from dolphinfit.core.bench.e2e_bench import checkout_label

    assert checkout_label(tmp_path) == tmp_path.name
    label = checkout_label(Path(__file__).resolve().parents[3])
    assert label and "/" not in label
