"""Project files: round trip, relative media paths, Save As, relink, autosave, bad input."""

import json
import os
import time
from pathlib import Path

import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.stations import STATION_PCT
from dolphinfit.core.project import edits, recent
from dolphinfit.core.project.project_file import (
    autosave_path, find_moved_media, has_newer_autosave, media_path, missing_media,
    project_from_json, project_to_json, read_project, rebase_media, relink_clip, write_project,
)
from dolphinfit.core.project.model import MeasurementKey, get_measurement, with_measurement


def _same(a, b) -> None:
    assert project_to_json(a) == project_to_json(b)
    for ca, cb in zip(a.clips, b.clips):
        for aa, ab in zip(ca.animals, cb.animals):
            for ma, mb in zip(aa.measurements, ab.measurements):
                np.testing.assert_array_equal(ma.midline_px, mb.midline_px)
                np.testing.assert_array_equal(ma.offsets_px, mb.offsets_px)


def test_round_trip_keeps_everything(tmp_path, project):
    path = tmp_path / "survey.dolphinfit"
    write_project(path, project)
    back = read_project(path)
    _same(project, back)
    assert back.clips[0].animals[0].notes == "scar on the dorsal fin"
    assert back.clips[0].altitude.constant_m == 18.0
    assert back.clips[0].animals[0].fit_settings == project.clips[0].animals[0].fit_settings
    assert back.clips[0].scan_path == "p.scans/clip_scan.json"
    assert back.clips[0].rejected_frames == ((1, 10), (2, 40))  # in order
    data = json.loads(path.read_text())
    assert data["schema_version"] == 1
    assert data["clips"][0]["media"] == "media/clip.mp4"          # relative, POSIX
    assert "altitude_m" not in json.dumps(data["clips"][0]["animals"])  # pixels apart


def test_edge_sources_are_kept(tmp_path, project):
    """Suggested, suggested-then-moved and clicked edges come back as they were saved."""
    key = MeasurementKey(0, 0, 0)
    m = get_measurement(project, key)
    stations = edits.stations_of(m)
    edges = stations.points_px[:, None, :] + np.full((19, 2, 1), 30.0) * stations.normals[:, None]
    m = edits.set_offset(edits.move_offset(edits.offsets_from_edges(m, edges, False),
                                           4, 1, -33.0), 6, 0, 41.0)
    path = tmp_path / "p.dolphinfit"
    write_project(path, with_measurement(project, key, m))
    back = get_measurement(read_project(path), key)
    np.testing.assert_array_equal(back.edge_sources, m.edge_sources)
    assert back.edge_sources[4, 1] == "suggested_moved" and back.edge_sources[6, 0] == "clicked"
    station = json.loads(path.read_text())["clips"][0]["animals"][0]["measurements"][0][
        "stations"][6]
    assert station["side_b_source"] == "suggested" and "side_a_source" not in station  # clicked


def test_file_from_before_edge_sources_reads_its_edges_as_clicked():
    """A measurement written without sources (every file before them) opens, edges clicked."""
    stations = [{"station_pct": pct, "side_a_px": 20.0, "side_b_px": None if i == 3 else -20.0,
                 "skipped": False} for i, pct in enumerate(STATION_PCT.tolist())]
    data = {"schema_version": 1, "settings": {"hw_ratios": "tursiops-provisional",
                                              "tail": "extrapolated"},
            "clips": [{"media": "clip.mp4", "kind": "video", "masks": None,
                       "camera": {"preset": None, "focal_mm": 12.29, "sensor_width_mm": 17.27,
                                  "image_width_px": 1280, "image_height_px": 720},
                       "altitude": None, "altitude_calibration": None,
                       "animals": [{"id": "dolphin 1", "notes": "", "measurements": [{
                           "frame_idx": 3, "midline_px": [[100, 300], [900, 320]],
                           "mirror_side": None, "notes": "", "stations": stations}]}]}]}
    m = get_measurement(project_from_json(data, "old.dolphinfit"), MeasurementKey(0, 0, 0))
    assert m.edge_sources[3, 1] == ""
    assert (np.delete(m.edge_sources.ravel(), 3 * 2 + 1) == "clicked").all()


def test_save_as_elsewhere_rebases_relative_paths(tmp_path, project):
    media = tmp_path / "media"
    media.mkdir()
    (media / "clip.mp4").write_bytes(b"x")
    moved = rebase_media(project, tmp_path, tmp_path / "out" / "deeper")
    assert moved.clips[0].media_path == "../../media/clip.mp4"
    assert moved.clips[0].masks_path == "../../media/masks"
    assert moved.clips[0].scan_path == "../../p.scans/clip_scan.json"
    assert moved.clips[0].animals[0].fit_path == "../../p.fits/clip_dolphin-1"
    assert media_path(tmp_path / "out" / "deeper" / "p.dolphinfit", moved.clips[0]) == \
        (media / "clip.mp4").resolve()


def test_moved_media_is_found_and_relinked(tmp_path, project):
    path = tmp_path / "p.dolphinfit"
    assert missing_media(path, project) == [0]
    new_home = tmp_path / "2024" / "day1"
    (new_home / "masks").mkdir(parents=True)
    (new_home / "clip.mp4").write_bytes(b"x")
    found = find_moved_media(tmp_path, "clip.mp4")
    assert found == [new_home / "clip.mp4"]
    relinked = relink_clip(project, path, 0, found[0])
    assert relinked.clips[0].media_path == "2024/day1/clip.mp4"
    assert relinked.clips[0].masks_path == "2024/day1/masks"  # moved along with the clip
    assert missing_media(path, relinked) == []


def test_autosave_newer_than_the_project_means_unsaved_work(tmp_path, project):
    path = tmp_path / "p.dolphinfit"
    write_project(path, project)
    assert not has_newer_autosave(path)
    write_project(autosave_path(path), project)
    assert autosave_path(path).name == "p.dolphinfit.autosave"
    assert has_newer_autosave(path)
    old = time.time() - 100
    os.utime(autosave_path(path), (old, old))
    assert not has_newer_autosave(path)


@pytest.mark.parametrize("mutate, message", [
    (lambda d: d.update(schema_version=99), "schema_version 99 was written by a newer "
                                            "dolphinfit"),
    (lambda d: d.update(schema_version=0), "schema_version 0 is not supported"),
    (lambda d: d["clips"][0].pop("camera"), "clips[0]: missing 'camera'"),
    (lambda d: d["clips"][0]["camera"].update(focal_mm="12"), "'focal_mm' has the wrong type"),
    (lambda d: d["clips"][0]["camera"].update(focal_mm=-1), "focal_mm"),
    (lambda d: d["clips"][0]["altitude"].update(constant_m=0), "positive"),
    (lambda d: d["clips"][0]["animals"][0]["measurements"][0]["stations"].pop(), "19 stations"),
    (lambda d: d["clips"][0]["animals"][0]["measurements"][0].update(midline_px=[[1, True]]),
     "midline_px[0]"),
    (lambda d: d["clips"][0]["animals"][0]["measurements"][0].update(mirror_side="C"),
     "mirror_side"),
    (lambda d: d["clips"][0].update(kind="film"), "media kind"),
    (lambda d: d["settings"].update(tail="cut"), "tail"),
    (lambda d: d["clips"][0].update(rejected_frames=[[1, -3]]), "rejected_frames: expected"),
    (lambda d: d["clips"][0].update(rejected_frames=[1, 3]), "rejected_frames: expected"),
    (lambda d: d["clips"][0]["animals"][0]["fit"]["settings"].update(quality="best"),
     "quality"),
    (lambda d: d["clips"][0]["animals"][0]["fit"]["settings"].update(end_s=-1.0), "end"),
    (lambda d: d["clips"][0]["animals"][0]["measurements"][0]["stations"][0].update(
        side_a_source="guessed"), "measurements[0]: edge sources"),
])
def test_bad_files_name_the_entry(project, mutate, message):
    data = project_to_json(project)
    mutate(data)
    with pytest.raises(InputError, match=message.replace("[", r"\[").replace("]", r"\]")):
        project_from_json(json.loads(json.dumps(data)), "p.dolphinfit")


def test_not_json_names_the_file(tmp_path):
    path = tmp_path / "p.dolphinfit"
    path.write_text("{ not json")
    with pytest.raises(InputError, match="p.dolphinfit: not valid JSON"):
        read_project(path)


def test_recent_projects_newest_first_and_existing_only(tmp_path, monkeypatch):
    monkeypatch.setenv("DOLPHINFIT_CONFIG_DIR", str(tmp_path / "config"))
    paths = [tmp_path / f"p{i}.dolphinfit" for i in range(3)]
    for p in paths:
        p.write_text("{}")
        recent.add_recent(p)
    recent.add_recent(paths[0])
    assert recent.recent_projects() == [paths[0], paths[2], paths[1]]
    paths[2].unlink()
    assert recent.recent_projects() == [paths[0], paths[1]]
    for i in range(15):
        (tmp_path / f"q{i}.dolphinfit").write_text("{}")
        recent.add_recent(tmp_path / f"q{i}.dolphinfit")
    assert len(recent.recent_projects()) == recent.MAX_RECENT
    assert isinstance(recent.recent_path(), Path)


def test_the_projects_own_hw_table_follows_save_as(tmp_path, project):
    from dataclasses import replace

    from dolphinfit.core.project.results import project_hw_spec

    own = replace(project, hw_ratios="p.fits/clip_dolphin-1_hw.csv")
    assert project_hw_spec(own, tmp_path) == str(tmp_path / "p.fits/clip_dolphin-1_hw.csv")
    assert project_hw_spec(project, tmp_path) == project.hw_ratios  # a preset name
    moved = rebase_media(own, tmp_path, tmp_path / "elsewhere")
    assert moved.hw_ratios == "../p.fits/clip_dolphin-1_hw.csv"
    assert rebase_media(project, tmp_path, tmp_path / "x").hw_ratios == project.hw_ratios


def test_a_clips_lens_model_round_trips_and_is_checked(tmp_path, project):
    from dataclasses import replace

    from dolphinfit.core.measure.lens import LensModel
    from dolphinfit.core.project.model import with_clip

    lens = LensModel(1280, 720, 900.0, 901.0, 639.5, 359.5, (-0.12, 0.05, 0.001, 0.0, 0.0),
                     0.05, 9, "boards of 3 May")
    with_lens = with_clip(project, 0, replace(project.clips[0], lens=lens))
    write_project(tmp_path / "p.dolphinfit", with_lens)
    assert read_project(tmp_path / "p.dolphinfit").clips[0].lens == lens
    assert "lens" not in project_to_json(project)["clips"][0]  # none: written as before
    data = json.loads(json.dumps(project_to_json(with_lens)))
    data["clips"][0]["lens"]["fx_px"] = -900.0
    with pytest.raises(InputError, match=r"clips\[0\]: lens: focal lengths"):
        project_from_json(data, "p.dolphinfit")
