"""`dolphinfit batch`: a bad manifest row is exit 2 naming it; a batch killed after its first
task and run again finishes the rest with nothing lost or duplicated."""

import csv
import os
import signal
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

from dolphinfit.app.cli import main
from dolphinfit.core.batch.record import RECORD_JSON
from dolphinfit.core.batch.summary import SUMMARY_CSV
from dolphinfit.core.bench.batch_bench import TINY_CONFIG, write_synthetic_batch
from dolphinfit.core.synth.config import Effects, SynthConfig

CLIP = SynthConfig(seed=51, width_px=320, height_px=180, fps=4.0, duration_s=1.0,
                   altitude_m=12.0, length_m=2.4, speed_m_s=0.5, dive_depth_m=0.0,
                   effects=Effects(profile_warp=False, scattering=False, ripples=False,
                                   glints=False, compression=False))
KILL_TIMEOUT_S = 180


def test_bad_row_exits_2_naming_manifest_row_and_column(tmp_path, capsys):
    (tmp_path / "a.mp4").write_bytes(b"x")
    manifest = tmp_path / "batch.csv"
    manifest.write_text("clip,altitude,fps\na.mp4,20,2\na.mp4,20,fast\n")
    assert main(["batch", str(manifest), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"{manifest}: row 3, column 'fps'" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


def _batch(manifest: Path, out: Path) -> list[str]:
    return [sys.executable, "-m", "dolphinfit.app.cli", "batch", str(manifest), "--out", str(out),
            "--workers", "1", "--mc", "100"]


def _finished(out: Path) -> list[Path]:
    """Records of the tasks in place (not in a hidden partial folder)."""
    return sorted(p for p in out.glob(f"*/{RECORD_JSON}") if not p.parent.name.startswith("."))


def test_killed_batch_rerun_finishes_the_rest(tmp_path):
    clips = [replace(CLIP, seed=51 + i, heading_deg=60.0 * i) for i in range(2)]
    manifest = write_synthetic_batch(tmp_path / "data", clips, replace(TINY_CONFIG, fps=2.0))
    out = tmp_path / "out"
    env = {**os.environ, "DOLPHINFIT_THREADS": "1"}
    batch = subprocess.Popen(_batch(manifest, out), env=env, start_new_session=True,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + KILL_TIMEOUT_S
    while not _finished(out) and batch.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    os.killpg(batch.pid, signal.SIGKILL)  # the batch and its Dask workers
    batch.wait()
    first = _finished(out)
    assert len(first) == 1 and not (out / SUMMARY_CSV).exists()  # killed mid-batch
    first_record = first[0].read_bytes()
    first_mtime = first[0].stat().st_mtime_ns

    rerun = subprocess.run(_batch(manifest, out), env=env, capture_output=True, text=True,
                           timeout=KILL_TIMEOUT_S)
    assert rerun.returncode == 0, rerun.stderr
    assert "1 finished before" in rerun.stdout and "(finished before)" in rerun.stdout
    with open(out / SUMMARY_CSV, newline="") as file:
        rows = list(csv.DictReader(file))
    assert len(rows) == 2 and {r["status"] for r in rows} == {"complete"}
    assert len({r["folder"] for r in rows}) == 2
    assert sorted(r["reused"] for r in rows) == ["no", "yes"]
    # the finished task was not run again; nothing half-written is left
    assert first[0].read_bytes() == first_record and first[0].stat().st_mtime_ns == first_mtime
    assert sorted(p.name for p in out.iterdir()) == sorted([SUMMARY_CSV,
                                                            *(r["folder"] for r in rows)])
    for row in rows:
        assert (out / row["folder"] / "result.json").is_file()
        assert (out / row["folder"] / "elliptical_measure.json").is_file()
