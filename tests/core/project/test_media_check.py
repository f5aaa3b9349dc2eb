"""A clip's media fingerprint: taken when the clip is added, unchanged by a copy or a move,
changed by a re-encode, a trim or another file under the same name; changed clips listed and
re-stamped only when asked."""

import shutil

import numpy as np

from dolphinfit.core.io.media_fingerprint import CHUNK_BYTES, changed_fingerprint, media_fingerprint
from dolphinfit.core.project.media_check import changed_media, with_media_accepted
from dolphinfit.core.project.model import Project
from dolphinfit.core.project.project_file import read_project, write_project
from dolphinfit.core.project.new_project import clip_entry_for


class _Source:
    """What ``clip_entry_for`` reads of opened media."""

    kind = "video"

    class clip:
        width_px, height_px = 1280, 720


def _media(path, size=3 * CHUNK_BYTES, seed=0):
    path.write_bytes(np.random.default_rng(seed).integers(0, 256, size, np.uint8).tobytes())
    return path


def test_the_fingerprint_sees_edits_at_either_end_and_a_new_size(tmp_path):
    clip = _media(tmp_path / "clip.mp4")
    print_ = media_fingerprint(clip)
    assert print_.startswith("v1:") and changed_fingerprint(print_, clip) is None
    shutil.copy(clip, tmp_path / "copy.mp4")
    assert media_fingerprint(tmp_path / "copy.mp4") == print_
    data = bytearray(clip.read_bytes())
    for where in (10, len(data) - 10):
        edited = bytearray(data)
        edited[where] ^= 0xFF
        clip.write_bytes(bytes(edited))
        assert changed_fingerprint(print_, clip) == media_fingerprint(clip) != print_
    clip.write_bytes(bytes(data[:-1]))                 # a trim
    assert changed_fingerprint(print_, clip) == media_fingerprint(clip) != print_
    assert changed_fingerprint("v0:anything", clip) is None   # another recipe: not compared


def test_changed_clips_are_listed_and_stamped_again_only_when_asked(tmp_path):
    project_path = tmp_path / "survey.dolphinfit"
    entries = [clip_entry_for(_media(tmp_path / f"{name}.mp4", seed=i), tmp_path, _Source)[0]
               for i, name in enumerate(("a", "b"))]
    project = Project(clips=tuple(entries))
    write_project(project_path, project)
    project = read_project(project_path)             # the fingerprint survives the file
    assert project.clips[0].media_fingerprint == entries[0].media_fingerprint
    assert changed_media(project, project_path) == {}
    _media(tmp_path / "b.mp4", seed=7)               # another clip copied over b.mp4
    (tmp_path / "a.mp4").unlink()                    # missing media: the relink's business
    changed = changed_media(project, project_path)
    assert changed == {1: media_fingerprint(tmp_path / "b.mp4")}
    accepted = with_media_accepted(project, changed)
    assert changed_media(accepted, project_path) == {}
    assert accepted.clips[0] is project.clips[0]


def test_a_frame_folder_changes_with_its_frames_not_with_a_browsers_files(tmp_path):
    for i in range(3):
        _media(tmp_path / f"frame_{i:04d}.png", size=1000, seed=i)
    print_ = media_fingerprint(tmp_path)
    (tmp_path / ".DS_Store").write_bytes(b"finder")
    (tmp_path / "Thumbs.db").write_bytes(b"explorer")
    assert media_fingerprint(tmp_path) == print_
    _media(tmp_path / "frame_0003.png", size=1000, seed=3)
    assert changed_fingerprint(print_, tmp_path) == media_fingerprint(tmp_path) != print_
