"""Atomic writes: files and folders are the old or the new, whole, even after a kill."""

import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import dolphinfit.core.io.atomic as atomic
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.atomic import atomic_folder, atomic_path
from dolphinfit.core.io.masks import MaskTrack, write_masks
from dolphinfit.core.io.mesh_export import export_mesh

SLOW_WRITER = """
import sys, time
from pathlib import Path
import numpy as np
from dolphinfit.core.io.masks import MaskTrack, write_png_folder

def load(idx):
    time.sleep(0.02)
    mask = np.zeros((8, 8), bool)
    mask[2:4, 1:6] = True
    return mask

write_png_folder(MaskTrack(np.ones(500, bool), 8, 8, "slow", load), Path(sys.argv[1]))
"""


def _contents(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def _track(num_frames: int) -> MaskTrack:
    masks = np.zeros((num_frames, 8, 8), bool)
    masks[:, 3:5, 2:7] = True
    return MaskTrack.from_array(masks, "test")


def test_killed_mask_folder_write_leaves_the_old_masks(tmp_path):
    """SIGKILL while 500 new PNGs are written: the folder still holds the 3 old ones, intact;
    a rerun then replaces them with the complete new set."""
    folder = tmp_path / "masks"
    write_masks(_track(3), folder)
    old = _contents(folder)
    writer = subprocess.Popen([sys.executable, "-c", SLOW_WRITER, str(folder)],
                              cwd=Path(__file__).resolve().parents[3])
    deadline = time.monotonic() + 60
    while not any(len(list(tmp.glob("*.png"))) >= 20 for tmp in tmp_path.glob(".masks.*")):
        assert writer.poll() is None and time.monotonic() < deadline
        time.sleep(0.02)
    writer.send_signal(signal.SIGKILL)
    writer.wait()
    assert _contents(folder) == old
    write_masks(_track(7), folder)
    assert sorted(_contents(folder)) == [f"{t:06d}.png" for t in range(7)]


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "move-aside"])
def test_folder_swap_keeps_carried_files_and_leaves_nothing_behind(tmp_path, monkeypatch,
                                                                   exchange):
    """Success replaces the folder, carrying the files ``carry`` accepts; with or without a
    one-step exchange no temporary folder is left beside it."""
    if not exchange:
        monkeypatch.setattr(atomic, "_exchange", lambda a, b: False)
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "old.txt").write_text("old")
    (folder / ".keep").write_text("hidden")
    with atomic_folder(folder, carry=lambda p: p.name.startswith(".")) as tmp:
        (tmp / "new.txt").write_text("new")
    assert _contents(folder) == {".keep": b"hidden", "new.txt": b"new"}
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_failed_folder_write_leaves_the_old_folder(tmp_path):
    """An exception while filling the new folder leaves the old one as it was."""
    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "old.txt").write_text("old")
    with pytest.raises(RuntimeError), atomic_folder(folder) as tmp:
        (tmp / "new.txt").write_text("new")
        raise RuntimeError("disk full")
    assert _contents(folder) == {"old.txt": b"old"}
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_the_next_write_removes_what_a_killed_one_left_and_nothing_else(tmp_path):
    """A kill leaves hidden temporary folders beside the output (the new one, or the old
    one moved aside); the next write of that output removes them, but not another output's
    (``out.b``'s) nor a folder of another name."""
    for name in (".out.k3j_x9q2", ".out.old.a1b2c3d4", ".out.b.k3j_x9q2", ".out.notes",
                 "out.b"):
        (tmp_path / name).mkdir()
    with atomic_folder(tmp_path / "out") as tmp:
        (tmp / "new.txt").write_text("new")
    assert sorted(p.name for p in tmp_path.iterdir()) == [".out.b.k3j_x9q2", ".out.notes",
                                                          "out", "out.b"]


def test_outputs_under_a_file_or_onto_a_folder_are_input_errors(tmp_path):
    """A file path that is a folder, or any path under a file, is refused naming it."""
    blocker = tmp_path / "blocker"
    blocker.write_text("x")
    with pytest.raises(InputError, match=f"{blocker / 'a' / 'b.json'}: lies under {blocker}"):
        with atomic_path(blocker / "a" / "b.json"):
            pass
    with pytest.raises(InputError, match="is a folder"):
        with atomic_path(tmp_path):
            pass
    with pytest.raises(InputError, match="is a file, not a folder"):
        with atomic_folder(blocker):
            pass
    assert blocker.read_text() == "x"


def test_obj_export_writes_material_and_texture_whole(tmp_path):
    """An OBJ comes with its material and texture, each complete; no temporary files stay."""
    verts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    uvs = np.array([[0.1, 0.1], [0.9, 0.1], [0.1, 0.9], [0.9, 0.9]])
    export_mesh(tmp_path / "m.obj", verts, faces, uvs, faces, np.full((4, 4), 200, np.uint8))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.obj", "material.mtl",
                                                          "material_0.png"]
    assert "mtllib material.mtl" in (tmp_path / "m.obj").read_text()
    assert (tmp_path / "material_0.png").read_bytes().startswith(b"\x89PNG")
