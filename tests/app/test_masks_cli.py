"""`dolphinfit masks` driven through app.cli.main on a small clip of a dark moving ellipse."""

import importlib.util
from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.app.cli import main
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.io.video import open_clip

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


def _frame(clip: Path, t: int) -> np.ndarray:
    from dolphinfit.core.io.video import VideoReader
    with VideoReader(open_clip(clip)) as frames:
        return frames[t]


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
    (["--box", "500,500,20,20"], "--box: the box at (500, 500), 20×20 px, is not wholly "
                                 "inside the 160×120 frame"),
    (["--box", "150,10,20,20"], "is not wholly inside the 160×120 frame"),
    (["--seed", "160,10"], "--seed: the click (160, 10) lies outside the 160×120 frame"),
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


def test_every_fit_segments_the_frames_a_default_fit_takes(clip, tmp_path, capsys):
    """--every fit: masks on exactly the frames ``dolphinfit fit`` would take by default, so
    that a fit of them finds every frame it wants; a word other than 'fit' exits 2."""
    out = tmp_path / "masks.npz"
    assert main(["masks", str(clip), "--seed", "40,50", "--every", "fit", "--out",
                 str(out)]) == 0
    wanted = FitConfig().frames_of(open_clip(clip)).tolist()
    assert 1 < len(wanted) < 12
    assert list(np.flatnonzero(read_masks(out).is_visible)) == wanted
    assert main(["masks", str(clip), "--seed", "40,50", "--every", "fitted", "--out",
                 str(tmp_path / "m")]) == 2
    assert "--every 'fitted': expected a whole number" in capsys.readouterr().err


def test_a_still_image_gets_its_mask(clip, tmp_path, capsys):
    """A still (a PNG of the clip's frame 3) is found and written as one mask."""
    still = tmp_path / "DJI_0003.png"
    cv2.imwrite(str(still), cv2.cvtColor(_frame(clip, 3), cv2.COLOR_RGB2BGR))
    out = tmp_path / "still.npz"
    assert main(["masks", str(still), "--auto", "--backend", "colour", "--out", str(out)]) == 0
    assert f"wrote {out}: 1 frame, 1 with the animal" in capsys.readouterr().out
    got, truth = read_masks(out).mask(0), _truth(3)
    assert (got & truth).sum() / (got | truth).sum() > 0.85


def test_not_a_video_exits_2(tmp_path, capsys):
    """A text file named .mp4 exits with code 2 naming it."""
    bogus = tmp_path / "clip.mp4"
    bogus.write_text("not a video")
    assert main(["masks", str(bogus), "--auto", "--out", str(tmp_path / "m")]) == 2
    assert f"{bogus}: not a video" in capsys.readouterr().err


@pytest.mark.parametrize("args, problem", [
    (["--backend", "sam2"], "the sam2 back-end needs --sam2-checkpoint PATH"),
    (["--backend", "sam2", "--sam2-checkpoint", "{tmp}/gone.pt"],
     "--sam2-checkpoint {tmp}/gone.pt: no such file"),
    (["--backend", "sam2", "--sam2-checkpoint", "{tmp}/sam2.1_hiera_tiny.pth"],
     "--sam2-checkpoint {tmp}/sam2.1_hiera_tiny.pth: not a SAM-2 checkpoint (expected a .pt"),
    (["--backend", "sam2", "--sam2-checkpoint", "{tmp}"], "--sam2-checkpoint {tmp}: not a file"),
    (["--backend", "colour", "--sam2-checkpoint", "{tmp}/sam2.1_hiera_tiny.pt"],
     "--sam2-checkpoint {tmp}/sam2.1_hiera_tiny.pt: only used by the sam2 back-end"),
], ids=["no-checkpoint", "missing", "not-pt", "folder", "other-backend"])
def test_sam2_checkpoint_is_checked_before_any_work(clip, tmp_path, capsys, args, problem):
    """--sam2-checkpoint is required by --backend sam2 (an existing .pt file) and refused
    without it: exit 2 naming the option and the file."""
    (tmp_path / "sam2.1_hiera_tiny.pth").write_bytes(b"")
    (tmp_path / "sam2.1_hiera_tiny.pt").write_bytes(b"")
    args = [a.format(tmp=tmp_path) for a in args]
    out = tmp_path / "m"
    assert main(["masks", str(clip), "--seed", "40,50", *args, "--out", str(out)]) == 2
    assert problem.format(tmp=tmp_path) in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.skipif(importlib.util.find_spec("sam2") is not None,
                    reason="the sam2 package is installed here")
def test_sam2_without_its_package_exits_2_saying_how_to_install(clip, tmp_path, capsys):
    checkpoint = tmp_path / "sam2.1_hiera_tiny.pt"
    checkpoint.write_bytes(b"")
    assert main(["masks", str(clip), "--seed", "40,50", "--backend", "sam2",
                 "--sam2-checkpoint", str(checkpoint), "--out", str(tmp_path / "m")]) == 2
    err = capsys.readouterr().err
    assert "needs the 'sam2' package, which is not installed; install it yourself" in err
    assert "torchvision" in err
