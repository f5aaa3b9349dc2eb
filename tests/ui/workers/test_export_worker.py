"""ExportWorker: a saved still-image project exported off the GUI thread, with progress, the
receipt from the media, and cancel removing what was written."""

import csv
import json

import cv2
import numpy as np
import pytest

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.measure.annotation import place_stations
from dolphinfit.core.project.model import (
    AltitudeSpec, Animal, ClipEntry, Measurement, MeasurementKey, Project,
)
from dolphinfit.ui.workers.export_worker import ExportWorker

TIMEOUT_MS = 30_000
CAMERA = CameraPreset("test-720p", "", 8.8, 13.2, 1280, 720, "test", False)


def _measurement(top_px: float) -> Measurement:
    midline = np.array([[200.0, top_px], [1000.0, top_px + 60.0]])
    widths = 90.0 * np.sin(np.pi * place_stations(midline).fractions)
    return Measurement(0, midline, np.stack([widths / 2, -widths / 2], axis=1))


@pytest.fixture
def saved_project(tmp_path):
    """Two dolphins and one animal without a length on a still beside the project file."""
    still = np.full((720, 1280, 3), (20, 60, 110), np.uint8)
    cv2.imwrite(str(tmp_path / "still.png"), cv2.cvtColor(still, cv2.COLOR_RGB2BGR))
    animals = (Animal("dolphin 1", measurements=(_measurement(200.0),)),
               Animal("dolphin 2", measurements=(_measurement(450.0),)),
               Animal("dolphin 3", measurements=(Measurement(0),)))
    clip = ClipEntry("still.png", "image", CAMERA,
                     altitude=AltitudeSpec(constant_m=15.0, source="laser"), animals=animals)
    keys = [MeasurementKey(0, a, 0) for a in range(3)]
    return Project(clips=(clip,)), tmp_path / "survey.dolphinfit", keys, still


@pytest.fixture
def worker(qtbot):
    export_worker = ExportWorker(num_draws=200)
    yield export_worker
    export_worker.shutdown()


def test_exports_with_progress_and_receipts(worker, saved_project, qtbot, tmp_path):
    project, path, keys, still = saved_project
    steps = []
    worker.progress.connect(lambda p: steps.append((p.stage, p.step, p.total)))
    with qtbot.waitSignal(worker.finished, timeout=TIMEOUT_MS) as blocker:
        worker.start(project, path, keys, tmp_path / "out", "survey")
    paths, skipped = blocker.args[0]
    assert steps == [("measure", 1, 6), ("measure", 2, 6), ("measure", 3, 6),
                     ("write", 5, 6), ("write", 6, 6)]  # one frame left out: ends at 6 of 6
    assert len(skipped) == 1 and skipped[0].startswith("still.png frame 0: no body length")
    receipt = cv2.imread(str(tmp_path / "out" / "survey_receipts" / "still_dolphin-1.png"))
    assert receipt.shape == still.shape and not np.array_equal(receipt[..., ::-1], still)
    with (tmp_path / "out" / "survey_wide.csv").open(newline="", encoding="utf-8") as file:
        rows = list(csv.DictReader(file))
    assert [row["animal_id"] for row in rows] == ["dolphin 1", "dolphin 2"]
    assert all(float(row["volume_m3_lo95"]) < float(row["volume_m3"]) for row in rows)
    assert set(paths) == {p for p in (tmp_path / "out").rglob("*") if p.is_file()}
    annotations = tmp_path / "out" / "survey_annotations"
    media = json.loads((annotations / "still_dolphin-1.json").read_text(encoding="utf-8"))[
        "image"]["media_path"]
    assert (annotations / media).resolve() == (tmp_path / "still.png").resolve()
    assert not worker.is_running


def test_cancel_leaves_nothing(saved_project, qtbot, tmp_path):
    project, path, keys, _ = saved_project
    slow = ExportWorker(num_draws=20_000)  # each frame takes a while: the cancel lands first
    slow.progress.connect(lambda _: slow.cancel())
    try:
        with qtbot.waitSignal(slow.cancelled, timeout=TIMEOUT_MS):
            slow.start(project, path, keys, tmp_path / "out", "survey")
    finally:
        slow.shutdown()
    assert not (tmp_path / "out").exists() and not slow.is_running
