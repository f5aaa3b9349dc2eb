"""A batch on a Dask cluster: both methods' figures, a record per task, reruns that skip
finished tasks, retry failed ones on request and rerun those whose inputs changed."""

import csv
import json
import shutil
from dataclasses import replace

import pytest

from dolphinfit.core.batch.cluster import batch_client, local_plan
from dolphinfit.core.batch.inputs import inputs_digest, task_inputs
from dolphinfit.core.batch.manifest import read_manifest
from dolphinfit.core.batch.record import RECORD_JSON
from dolphinfit.core.batch.runner import run_batch
from dolphinfit.core.batch.summary import SUMMARY_CSV
from dolphinfit.core.bench.batch_bench import TINY_CLIP, TINY_CLIP_CONFIG, write_synthetic_batch

CLIP, FIT = TINY_CLIP, TINY_CLIP_CONFIG   # 4 frames, 2 of them fitted, one step each


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    """Two clips; the second's masks are empty, so its fit fails until they are restored."""
    folder = tmp_path_factory.mktemp("batch")
    manifest = write_synthetic_batch(folder, [CLIP, replace(CLIP, seed=42)], FIT)
    shutil.move(folder / "clip1" / "masks", folder / "clip1" / "true_masks")
    (folder / "clip1" / "masks").mkdir()
    return folder, read_manifest(manifest, num_draws=200)


@pytest.fixture(scope="module")
def client():
    with batch_client(plan=local_plan(1, 1), processes=False) as client:
        yield client


def _summary(out_dir):
    with open(out_dir / SUMMARY_CSV, newline="") as file:
        return list(csv.DictReader(file))


def _record_times(out_dir, tasks):
    return [(out_dir / t.name / RECORD_JSON).stat().st_mtime_ns for t in tasks]


def test_batch_runs_resumes_and_retries(batch, client, tmp_path):
    folder, tasks = batch
    out = tmp_path / "out"
    good, bad = run_batch(client, tasks, out)
    assert (good.status, bad.status) == ("complete", "failed")
    assert "fit:" in bad.error and "masks" in bad.error
    truth = json.loads((folder / "clip0" / "truth.json").read_text())
    rows = _summary(out)
    assert [r["status"] for r in rows] == ["complete", "failed"]
    row = rows[0]
    for method in ("fit", "ell"):  # one step per stage: the initial size from the masks
        assert abs(float(row[f"length_m_{method}"]) / truth["length_m"] - 1) < 0.1
    for key in ("length_m", "volume_m3", "bci", "mass_kg"):
        for method in ("ell", "fit"):
            assert (float(row[f"{key}_{method}_lo95"]) < float(row[f"{key}_{method}"])
                    < float(row[f"{key}_{method}_hi95"]))
    assert 0.2 < float(row["mass_kg_ell"]) / float(row["mass_kg_fit"]) < 5
    assert int(row["fit_frames"]) == 2 and row["reused"] == "no"
    produced = {p.name for p in (out / good.name).iterdir()}
    assert {"task.json", "result.json", "rest_mesh.ply", "elliptical_measure.json"} <= produced
    assert sorted(p.name for p in out.iterdir()) == sorted([SUMMARY_CSV, good.name, bad.name])

    # a rerun skips both: the complete one, and the failed one without --retry-failed
    before = _record_times(out, tasks)
    again = run_batch(client, tasks, out)
    assert [r.reused for r in again] == [True, True] and _record_times(out, tasks) == before
    assert [r["reused"] for r in _summary(out)] == ["yes", "yes"]

    # --retry-failed runs the failed one only
    retried = run_batch(client, tasks, out, retry_failed=True)
    assert [r.reused for r in retried] == [True, False] and retried[1].status == "failed"

    # its inputs changed (the masks restored): it runs again without being asked
    shutil.rmtree(folder / "clip1" / "masks")
    shutil.copytree(folder / "clip1" / "true_masks", folder / "clip1" / "masks")
    fixed = run_batch(client, tasks, out)
    assert [r.reused for r in fixed] == [True, False]
    assert [r.status for r in fixed] == ["complete", "complete"]
    assert _record_times(out, tasks)[0] == before[0]


def test_inputs_digest_follows_content_and_options(batch, tmp_path):
    folder, tasks = batch
    task = tasks[0]
    digest = inputs_digest(task_inputs(task))
    moved = tmp_path / "moved"
    shutil.copytree(folder / "clip0", moved)
    same_files = replace(task, fit=replace(task.fit, clip=moved / task.fit.clip.name,
                                           masks=moved / "masks"))
    assert inputs_digest(task_inputs(same_files)) == digest
    other_fps = replace(task, fit=replace(task.fit, config=replace(task.fit.config, fps=1.0)))
    assert inputs_digest(task_inputs(other_fps)) != digest
    (moved / "masks" / "000000.png").unlink()
    assert inputs_digest(task_inputs(same_files)) != digest


def test_inputs_digest_takes_the_hw_tables_values_not_its_place(batch, tmp_path):
    """A fit's HW table enters the digest by its values: the same table in another folder is
    the same input, the table edited in place is a new one."""
    from dolphinfit.core.measure.hw_ratios import load_hw_preset, write_hw_csv

    _, tasks = batch
    task = tasks[0]
    table = load_hw_preset()
    digests = []
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        write_hw_csv(tmp_path / folder / "hw.csv", table)
        config = replace(task.fit.config, hw_table=str(tmp_path / folder / "hw.csv"))
        digests.append(inputs_digest(task_inputs(replace(task, fit=replace(task.fit,
                                                                           config=config)))))
    assert digests[0] == digests[1]
    write_hw_csv(tmp_path / "b" / "hw.csv", replace(table, ratios=table.ratios * 1.1))
    config = replace(task.fit.config, hw_table=str(tmp_path / "b" / "hw.csv"))
    assert inputs_digest(task_inputs(replace(task, fit=replace(task.fit, config=config)))) \
        != digests[0]


def test_a_calibrated_task_corrects_both_methods_altitudes(batch, tmp_path):
    """An altitude calibration of the clip's camera (true = 0.5 m + 1.02 × recorded): the
    fit's and the elliptical's altitudes are the calibrated 12.7 m, not the recorded 12 m,
    and the elliptical's altitude error is the calibration's ~1 %, not the manual 10 %."""
    from dolphinfit.core.batch.task_run import run_task
    from dolphinfit.core.io.video import open_clip
    from tests.core.measure.test_altitude_calibration import _calibration

    _, tasks = batch
    task = tasks[0]
    intrinsics = task.fit.camera.intrinsics(open_clip(task.fit.clip))
    calibration = _calibration()
    calibration = replace(calibration, camera=replace(
        calibration.camera, image_width_px=320,
        focal_mm=intrinsics.focal_px * calibration.camera.sensor_width_mm / 320))
    task = replace(task, fit=replace(task.fit, altitude_calibration=calibration))
    record = run_task(task, tmp_path / "out")
    assert record.status == "complete", record.error
    elliptical = json.loads((tmp_path / "out" / task.name / "elliptical_measure.json")
                            .read_text())
    recorded = elliptical["recorded_altitude_m"]
    assert recorded == pytest.approx(12.0, abs=0.1)   # the SRT's, as the clip was flown
    assert elliptical["altitude_m"] == pytest.approx(calibration.true_altitude(recorded))
    assert elliptical["uncertainty"]["errors"]["altitude_sd_fraction"] < 0.02


def test_a_scans_best_frames_are_tracked_and_measured(batch, tmp_path):
    """A row naming the clip's scan: the elliptical method measures the animal's best frames
    (here frames 3 and 1 of 4: frame 3 is not one the fit uses, so the tracker draws it too),
    each exported, the summary taking the frame of median volume."""
    from dolphinfit.core.batch.task_run import run_task
    from dolphinfit.core.scan.clip_scan import ClipScan
    from dolphinfit.core.scan.frame_scores import FrameScore, ScanSettings
    from dolphinfit.core.scan.scan_files import write_scan_json

    from dolphinfit.core.synth.files import clip_files

    folder, _ = batch
    video = clip_files(folder / "clip0", CLIP).video
    truth = json.loads((folder / "clip0" / "truth.json").read_text())

    def score(frame: int, quality: float) -> FrameScore:
        centre = truth["frames"][frame]["seed_px"]
        return FrameScore(1, frame, frame / 4, centre[0], centre[1], 45.0, 2.3, 1.0, 1.0, 1.0,
                          30.0, 12.0, -90.0, 1.0, 1.0, 1.0, quality, ())
    scans = tmp_path / "scans"
    scans.mkdir()
    write_scan_json(scans / f"{video.stem}_scan.json", ClipScan(
        video.name, 4.0, 4, 320, 180, (0, 1, 2, 3), ScanSettings(best_count=2),
        (score(0, 0.5), score(1, 0.8), score(2, 0.6), score(3, 0.9)), 1.0))
    manifest = tmp_path / "manifest.csv"
    manifest.write_text(
        "clip,animal,altitude,camera,sensor_width_mm,focal_mm,config,scan\n"
        f"{video},1,{folder}/clip0/altitude.csv,,{CLIP.sensor_width_mm},"
        f"{CLIP.focal_mm},{folder}/fit_config.json,{scans}\n")
    (task,) = read_manifest(manifest, num_draws=50)
    assert task.measurement.frames == (1, 3) and task.fit.also_frames == (1, 3)
    assert (task.fit.seed.frame_idx, task.fit.masks) == (3, None)
    record = run_task(task, tmp_path / "out")
    out = tmp_path / "out" / task.name
    assert {"elliptical_clip_f000001_measure.json",
            "elliptical_clip_f000003_measure.json"} <= {p.name for p in out.iterdir()}
    assert "median volume of 2 best frames" in record.values["notes"], record.error
    volumes = {frame: json.loads((out / f"elliptical_clip_f{frame:06d}_measure.json")
                                 .read_text())["volume_m3"] for frame in (1, 3)}
    assert record.values["ell_frame"] == min(volumes, key=volumes.get)  # the lower of two
    assert record.values["volume_m3_ell"] == pytest.approx(min(volumes.values()))


def test_a_lost_worker_does_not_run_finished_tasks_again(tmp_path):
    """The worker that ran a task is killed once the task's record is taken: the task does
    not run again (Dask recomputes lost results a client still holds; a failed task, retried,
    would complete a second time), and the batch finishes on the restarted worker."""
    import os
    import time

    import psutil

    from dolphinfit.core.batch.cluster import ClusterPlan, batch_client
    from dolphinfit.core.batch.task import BatchTask, MaskMeasurement

    no_fit, other = (BatchTask(name, "none", "1", "test", None, MaskMeasurement(num_draws=0))
                     for name in ("no_fit", "other"))
    record_file = tmp_path / "out" / no_fit.name / RECORD_JSON
    first = {}
    with batch_client(plan=ClusterPlan(1, 1)) as client:
        (worker,) = client.run(os.getpid).values()

        def kill_the_worker(i, record):
            if i == 0:
                first["stat"] = record_file.stat()
                deadline = time.monotonic() + 5  # until the cluster has let the result go
                while any(client.has_what().values()) and time.monotonic() < deadline:
                    time.sleep(0.05)
                psutil.Process(worker).kill()

        records = run_batch(client, [no_fit, other], tmp_path / "out", retry_failed=True,
                            on_record=kill_the_worker)
    assert [r.status for r in records] == ["failed", "failed"]
    assert all("there is no fit" in r.error for r in records)
    now = record_file.stat()
    assert (now.st_ino, now.st_mtime_ns) == (first["stat"].st_ino, first["stat"].st_mtime_ns)
