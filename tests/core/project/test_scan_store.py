"""A clip's scan kept with its project: where it is written, what the clip list says of each
clip, and which clip needs work next."""

from dataclasses import replace

from dolphinfit.core.project.model import Animal, Measurement
from dolphinfit.core.project.scan_store import (
    clip_status, next_clip_needing_work, save_scan, scan_animal, scan_file,
)
from dolphinfit.core.scan.clip_scan import ClipScan
from dolphinfit.core.scan.frame_scores import FrameScore, ScanSettings
from dolphinfit.core.scan.scan_files import read_scan_json


def _score(animal: int, frame: int, quality: float, faults: tuple[str, ...] = ()) -> FrameScore:
    return FrameScore(animal_id=animal, frame_idx=frame, time_s=frame / 10, centre_x_px=100.0,
                      centre_y_px=80.0, length_px=200.0, length_m=2.4, straightness=0.99,
                      sharpness=50.0, contrast=20.0, border_px=40.0, altitude_m=18.0,
                      gimbal_pitch_deg=-89.0, length_share=1.0, sharpness_share=1.0,
                      contrast_share=1.0, quality=quality, faults=faults)


SCAN = ClipScan("clip.mp4", 10.0, 50, 1280, 720, (0, 10, 20), ScanSettings(), (
    _score(1, 0, 0.8), _score(1, 10, 0.9),
    _score(2, 10, 0.5, ("at the frame's edge",)), _score(2, 20, 0.4, ("at the frame's edge",)),
), 3.0)


def test_the_scan_is_kept_beside_the_project_with_its_csv(tmp_path, project):
    path = scan_file(tmp_path / "p.dolphinfit", project.clips[0].media_path)
    assert path.parent == tmp_path / "p.scans" and path.name.endswith("_scan.json")
    assert path.name.startswith("clip")  # the clip key: its stem and a hash of its path
    save_scan(SCAN, path)
    assert read_scan_json(path) == SCAN
    assert path.with_suffix(".csv").read_text().count("\n") == 1 + len(SCAN.scores)


def test_the_status_counts_animals_found_usable_measured_and_fitted(project):
    clip = project.clips[0]  # "dolphin 1" measured twice and fitted; "dolphin 2" not measured
    assert scan_animal(clip, 1) == 0 and scan_animal(clip, 3) is None
    unscanned = clip_status(clip, None)
    assert unscanned.text() == "not scanned · 2 measured · 1 fitted" and unscanned.needs_work
    status = clip_status(clip, SCAN)
    # animal 2 has no usable frame (always at the edge): only animal 1 must be measured
    assert (status.animals_found, status.animals_usable, status.animals_measured) == (2, 1, 1)
    assert status.text() == "2 found · 2 measured · 1 fitted" and not status.needs_work
    # every usable frame of animal 1 put aside: nothing is left to measure of it
    aside = replace(clip, animals=(), rejected_frames=((1, 0), (1, 10)))
    assert clip_status(aside, SCAN).animals_usable == 0 and not clip_status(aside, SCAN).needs_work
    assert clip_status(replace(aside, rejected_frames=((1, 0),)), SCAN).needs_work
    unmeasured = replace(clip, animals=(Animal("dolphin 1"),), altitude=None)
    status = clip_status(unmeasured, SCAN)
    assert status.needs_work and status.text() == "no altitude · 2 found · 0 measured"
    # a frame opened for measuring, its length not clicked yet, is not measured
    opened = replace(clip.animals[0], measurements=(Measurement(frame_idx=10),), fit_path=None)
    status = clip_status(replace(clip, animals=(opened,)), SCAN)
    assert status.needs_work and status.text() == "2 found · 0 measured"


def test_a_clip_where_the_scan_found_nothing_is_not_done_until_someone_looks(project):
    """A scan that found no animal may have missed it: the clip reads "none found: check"
    and needs work (Ctrl+J stops there) until a frame of it is measured."""
    empty = replace(SCAN, scores=())
    clip = replace(project.clips[0], animals=())
    status = clip_status(clip, empty)
    assert status.none_found and status.needs_work
    assert status.text() == "none found: check · 0 measured"
    measured = clip_status(project.clips[0], empty)
    assert not measured.none_found and not measured.needs_work
    assert measured.text() == "0 found · 2 measured · 1 fitted"
    assert next_clip_needing_work([clip_status(project.clips[0], SCAN), status], after=0) == 1


def test_the_next_clip_needing_work_wraps_round(project):
    clip = project.clips[0]
    done, todo = clip_status(clip, SCAN), clip_status(clip, None)
    assert next_clip_needing_work([todo, done, todo], after=0) == 2
    assert next_clip_needing_work([todo, done, done], after=0) == 0
    assert next_clip_needing_work([done, done], after=1) is None
    assert next_clip_needing_work([done, todo], after=None) == 1
