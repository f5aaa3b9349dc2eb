"""`dolphinfit scan` on the sample clip (one dolphin beside a patch of glitter) and on bad
input."""

import csv
import json

import pytest

from dolphinfit.app.cli import main
from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.io.video import open_clip
from dolphinfit.core.scan.scan_files import read_scan_json
from dolphinfit.core.synth.sample import SAMPLE_CONFIG, ensure_sample


@pytest.fixture(scope="module")
def scanned(tmp_path_factory):
    """The sample clip scanned once a second, with its own camera and SRT."""
    files = ensure_sample()
    out = tmp_path_factory.mktemp("scan")
    code = main(["scan", str(files.video), "--out", str(out), "--fps", "1",
                 "--sensor-width-mm", str(SAMPLE_CONFIG.sensor_width_mm),
                 "--focal-mm", str(SAMPLE_CONFIG.focal_mm)])
    return code, files, out


def on_the_dolphin(truth, score) -> bool:
    return bool(truth.mask(score.frame_idx)[round(score.centre_y_px), round(score.centre_x_px)])


def test_the_scan_follows_the_dolphin_in_every_sample(scanned):
    code, files, out = scanned
    assert code == 0
    scan = read_scan_json(out / f"{files.video.stem}_scan.json")
    assert scan.sampled_frames == (0, 10, 20, 30, 40)
    truth = read_masks(files.masks_dir, open_clip(files.video))
    dolphin = scan.of_animal(1)
    assert [s.frame_idx for s in dolphin] == [0, 10, 20, 30, 40]
    assert all(on_the_dolphin(truth, score) for score in dolphin)
    # the glitter patch the network takes for an animal in 2 samples changes its length
    # from one to the other (2.11 m, 1.28 m): it is not kept as an animal
    assert scan.animal_ids() == [1]
    truth_length = json.loads(files.truth_json.read_text())["length_m"]
    best = scan.best(1)
    assert best and all(score.is_usable for score in best)
    # the scan's coarse look at the animal cuts rostrum and flukes short: 2.07 m of 2.45 m here
    assert 0.8 * truth_length < best[0].length_m < truth_length
    with (out / f"{files.video.stem}_scan.csv").open(newline="") as file:
        rows = list(csv.DictReader(file))
    assert [int(row["frame_idx"]) for row in rows] == [s.frame_idx for s in scan.scores]
    assert rows[[int(r["frame_idx"]) for r in rows].index(best[0].frame_idx)]["best_rank"] == "1"


@pytest.mark.parametrize("options, message", [
    (["--altitude-range", "30,10"], "--altitude-range '30,10': expected 0 < LOW < HIGH"),
    (["--altitude-range", "ten"], "--altitude-range 'ten': expected LOW,HIGH in metres"),
    (["--fps", "0"], "--fps"),
    (["--best", "0"], "--best"),
])
def test_bad_settings_are_refused_before_any_work(tmp_path, capsys, options, message):
    assert main(["scan", str(tmp_path), "--out", str(tmp_path / "out"), *options]) == 2
    assert message in capsys.readouterr().err


def test_a_folder_without_a_usable_clip_says_why(tmp_path, capsys):
    assert main(["scan", str(tmp_path), "--out", str(tmp_path / "out")]) == 2
    assert "no video in the folder" in capsys.readouterr().err
    (tmp_path / "broken.mp4").write_bytes(b"")
    (tmp_path / "other.mov").write_bytes(b"not a video")
    assert main(["scan", str(tmp_path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "not scanned: " in err and "broken.mp4" in err and "other.mov" in err
    assert "no clip could be scanned" in err
    assert not (tmp_path / "out").exists()
