"""`dolphinfit masks` driven through app.cli.main on a small clip of a dark moving ellipse."""

from pathlib import Path

import cv2
import numpy as np
import pytest

from app.cli import main
from core.io.masks import read_masks
from core.io.video import open_clip

NUM_FRAMES, WIDTH_PX, HEIGHT_PX = 12, 160, 120


def _centre(t: int) -> tuple[int, int]:
    return 40 + 6 * t, 50 + 2 * t


@pytest.fixture(scope="module")
def clip(tmp_path_factory) -> Path:
    """A dark grey ellipse (60×16 px) swimming across blue-green water, lossless."""
    path = tmp_path_factory.mktemp("clip") / "ellipse.mkv"
    rng = np.random.default_rng(1)
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"FFV1"), 25.0,
                             (WIDTH_PX, HEIGHT_PX))
    for t in range(NUM_FRAMES):
        frame = np.empty((HEIGHT_PX, WIDTH_PX, 3), np.uint8)
        frame[:] = (120, 104, 38)
        cv2.ellipse(frame, _centre(t), (30, 8), 15, 0, 360, (66, 66, 62), -1)
        noise = rng.normal(0, 3, frame.shape)
        writer.write(np.clip(frame + noise, 0, 255).astype(np.uint8))
    writer.release()
    return path


def _truth(t: int) -> np.ndarray:
    mask = np.zeros((HEIGHT_PX, WIDTH_PX), np.uint8)
    cv2.ellipse(mask, _centre(t), (30, 8), 15, 0, 360, 1, -1)
    return mask.astype(bool)


@pytest.mark.parametrize("seed", [["--auto"], ["--seed", "40,50"], ["--box", "5,35,72,32"]],
                         ids=["auto", "click", "box"])
def test_masks_written_as_pngs(clip, tmp_path, capsys, seed):
    """Each kind of seed writes one %06d.png per frame that matches the ellipse."""
    out = tmp_path / "masks"
    assert main(["masks", str(clip), *seed, "--backend", "colour", "--out", str(out)]) == 0
    assert f"wrote {out}: 12 frames, 12 with the animal" in capsys.readouterr().out
    assert len(list(out.glob("*.png"))) == NUM_FRAMES
    track = read_masks(out, open_clip(clip))
    for t in range(NUM_FRAMES):
        got, truth = track.mask(t), _truth(t)
        assert (got & truth).sum() / (got | truth).sum() > 0.85


def test_npz_output_and_later_seed_frame(clip, tmp_path):
    """--out x.npz writes one file; a seed in frame 6 tracks both ways."""
    out = tmp_path / "masks.npz"
    assert main(["masks", str(clip), "--seed", "76,62", "--frame", "6", "--backend", "colour",
                 "--out", str(out)]) == 0
    assert read_masks(out).is_visible.all()


@pytest.mark.parametrize("args, problem", [
    (["--seed", "12"], "--seed '12': expected 2 comma-separated numbers"),
    (["--seed", "150,110", "--backend", "colour"], "no dark, elongated animal found at the seed"),
    (["--seed", "150,110"], "the network found no animal at the seed"),
    (["--seed", "40,50", "--every", "0"], "--every: must be at least 1, got 0"),
    (["--auto", "--backend", "sam"], None),
    (["--auto", "--frame", "40"], "--frame 40"),
])
def test_bad_seeds_exit_2(clip, tmp_path, capsys, args, problem):
    """Malformed seeds, seeds on open water and frames outside the clip exit with code 2."""
    try:
        code = main(["masks", str(clip), *args, "--out", str(tmp_path / "m")])
    except SystemExit as exc:  # argparse refuses an unknown choice itself
        code = exc.code
    assert code == 2
    assert problem is None or problem in capsys.readouterr().err


def test_network_backend_on_every_kth_frame(clip, tmp_path, capsys):
    """The default back-end, the network, on every 4th frame: those frames match the ellipse,
    the others are written empty, and the summary says so."""
    out = tmp_path / "masks.npz"
    assert main(["masks", str(clip), "--seed", "40,50", "--every", "4", "--out", str(out)]) == 0
    assert "12 frames, 3 with the animal" in capsys.readouterr().out
    track = read_masks(out)
    assert list(np.flatnonzero(track.is_visible)) == [0, 4, 8]
    for t in (0, 4, 8):
        got, truth = track.mask(t), _truth(t)
        assert (got & truth).sum() / (got | truth).sum() > 0.85


def test_not_a_video_exits_2(tmp_path, capsys):
    """A text file named .mp4 exits with code 2 naming it."""
    bogus = tmp_path / "clip.mp4"
    bogus.write_text("not a video")
    assert main(["masks", str(bogus), "--auto", "--out", str(tmp_path / "m")]) == 2
    assert f"{bogus}: not a video" in capsys.readouterr().err
