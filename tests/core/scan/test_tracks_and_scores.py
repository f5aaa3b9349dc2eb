"""The scan's parts on analytic cases: following animals across samples, the measures of one
sighting, the faults and quality of a frame, the files, and the SRT's gimbal pitch."""

import csv
from dataclasses import replace

import cv2
import numpy as np
import pytest

from dolphinfit.core.io.srt import gimbal_pitch_at, parse_srt
from dolphinfit.core.scan.clip_scan import ClipScan
from dolphinfit.core.scan.frame_scores import (
    EDGE_MARGIN_PX, ScanSettings, best_frames, frame_faults, share_of_best, track_scores,
)
from dolphinfit.core.scan.scan_files import read_scan_json, write_scan_csv, write_scan_json
from dolphinfit.core.scan.sighting import Sighting, sighting
from dolphinfit.core.scan.tracks import MAX_UNSEEN_S, Track, Tracker

FPS = 10.0


def seen(frame_idx: int, x: float, y: float, length: float = 100.0, **measures) -> Sighting:
    values = dict(straightness=1.0, sharpness=100.0, contrast=20.0, border_px=200.0)
    values.update(measures)
    return Sighting(frame_idx, (int(x - length / 2), int(y - 10), int(length), 20), (x, y),
                    length, **values)


def test_two_animals_swimming_side_by_side_keep_their_numbers():
    tracker = Tracker(FPS)
    for step in range(6):
        frame = 10 * step   # one sample a second; each swims 60 px (1.5 m at 40 px/m) a second
        sightings = [seen(frame, 300 + 60 * step, 200), seen(frame, 300 + 60 * step, 260)]
        tracker.add(frame, sightings[::-1] if step % 2 else sightings, px_per_m=40.0)
    assert [len(t.sightings) for t in tracker.tracks] == [6, 6]
    assert {s.centre_px[1] for s in tracker.tracks[0].sightings} == {200}
    assert {s.centre_px[1] for s in tracker.tracks[1].sightings} == {260}


def test_a_touching_pair_keeps_its_numbers_where_the_nearest_match_would_swap_them():
    """The tuning split's touching pair, sampled once a second: 100 px a sample, the two 60 px
    apart. The nearer of the second sample's sightings to the first animal is the other's
    (67 px against 102); matched with the least distance in all, each keeps its own."""
    tracker = Tracker(FPS)
    tracker.add(0, [seen(0, 1026, 743, 174), seen(0, 988, 701, 157)], px_per_m=70.0)
    tracker.add(10, [seen(10, 977, 599, 159), seen(10, 1018, 641, 175)], px_per_m=70.0)
    tracker.add(20, [seen(20, 1001, 526, 174), seen(20, 957, 486, 160)], px_per_m=70.0)
    assert [[s.length_px for s in t.sightings] for t in tracker.tracks] == \
        [[174, 175, 174], [157, 159, 160]]


def test_no_sighting_or_no_track_matches_nothing():
    tracker = Tracker(FPS)
    tracker.add(0, [], px_per_m=40.0)
    tracker.add(10, [seen(10, 300, 300)], px_per_m=40.0)
    tracker.add(20, [], px_per_m=40.0)
    assert [len(t.sightings) for t in tracker.tracks] == [1]


def test_a_sighting_beyond_reach_is_another_animal():
    tracker = Tracker(FPS)
    tracker.add(0, [seen(0, 300, 300)], px_per_m=40.0)
    # one second later: reach = its length 100 px + 8 m/s × 1 s × 40 px/m = 420 px
    tracker.add(10, [seen(10, 300 + 400, 300), seen(10, 300 + 900, 300)], px_per_m=40.0)
    assert [len(t.sightings) for t in tracker.tracks] == [2, 1]


def test_a_track_unseen_too_long_is_closed():
    track = Track([seen(0, 100, 100)])
    last_open = int(MAX_UNSEEN_S * FPS)
    assert track.is_open(last_open, FPS) and not track.is_open(last_open + 1, FPS)


def test_the_prediction_follows_the_last_two_sightings():
    track = Track([seen(0, 100, 100), seen(10, 160, 130)])
    assert np.allclose(track.predicted_px(20), [220, 160])


def ellipse_frame(blur_sigma: float = 0.0, animal_grey: int = 200, bent: bool = False):
    """A light animal on dark water: an ellipse 200 × 40 px, or a bent band."""
    frame = np.full((400, 600, 3), 60, np.uint8)
    mask = np.zeros((400, 600), np.uint8)
    if bent:
        cv2.ellipse(mask, (300, 350), (150, 150), 0, 200, 340, 1, thickness=30)
    else:
        cv2.ellipse(mask, (300, 200), (100, 20), 0, 0, 360, 1, thickness=-1)
    frame[mask > 0] = animal_grey
    if blur_sigma:
        frame = cv2.GaussianBlur(frame, (0, 0), blur_sigma)
    return frame, mask > 0


def test_sighting_measures_follow_the_image():
    sharp_frame, mask = ellipse_frame()
    sharp = sighting(sharp_frame, mask, 0)
    assert sharp.length_px == pytest.approx(200, rel=0.05)
    assert sharp.straightness > 0.99
    assert sharp.centre_px == pytest.approx((300, 200), abs=1)
    assert sharp.border_px == pytest.approx(180, abs=1)
    assert sighting(ellipse_frame(blur_sigma=2.0)[0], mask, 0).sharpness < 0.3 * sharp.sharpness
    faint = sighting(ellipse_frame(animal_grey=90)[0], mask, 0)
    assert faint.contrast < 0.4 * sharp.contrast
    bent_frame, bent_mask = ellipse_frame(bent=True)
    assert sighting(bent_frame, bent_mask, 0).straightness < 0.9
    assert sighting(sharp_frame, np.zeros_like(mask), 0) is None


def test_shares_are_of_the_animals_best_and_capped():
    assert share_of_best(np.array([1.0, 2.0, 4.0, 4.0, 4.0])).tolist() == [0.25, 0.5, 1, 1, 1]
    assert share_of_best(np.zeros(3)).tolist() == [0, 0, 0]


def test_faults_name_why_a_frame_is_put_aside():
    settings = ScanSettings(altitude_range_m=(10.0, 30.0))
    good = seen(0, 300, 300)
    assert frame_faults(good, 0.95, 20.0, -89.0, settings) == ()
    assert frame_faults(replace(good, border_px=EDGE_MARGIN_PX - 1), 0.95, 20.0, np.nan,
                        settings) == ("at the frame's edge",)
    assert frame_faults(good, 0.7, 20.0, np.nan, settings) == (
        "70 % of its length: pitched, diving or arched",)
    assert frame_faults(good, 0.95, 35.0, np.nan, settings) == ("altitude 35.0 m outside 10–30 m",)
    assert frame_faults(good, 0.95, np.nan, np.nan, settings) == ("no altitude",)
    assert frame_faults(good, 0.95, 20.0, -70.0, settings) == ("gimbal pitch -70°",)


def scored_track():
    lengths = [100.0, 98.0, 80.0, 100.0, 99.0, 100.0]
    sightings = [seen(10 * i, 300, 300, length, sharpness=100.0 - 5 * i) for i, length in
                 enumerate(lengths)]
    altitude = np.full(60, 20.0)
    return track_scores(3, sightings, FPS, altitude, np.full(60, np.nan), 1000.0,
                        ScanSettings())


def test_quality_ranks_long_sharp_frames_first_and_leaves_out_short_ones():
    scores = scored_track()
    assert [s.animal_id for s in scores] == [3] * 6
    assert scores[0].length_m == pytest.approx(100 * 20 / 1000)
    assert not scores[2].is_usable   # 80 % of its best length
    best = best_frames(scores, 3)
    assert [s.frame_idx for s in best] == [0, 10, 30]   # a 2 % shorter, sharper frame first
    assert best[0].quality == pytest.approx(1.0)


def test_scan_files_read_back_equal_and_rank_the_best(tmp_path):
    scan = ClipScan("clip.mp4", FPS, 60, 600, 400, tuple(range(0, 60, 10)),
                    ScanSettings(best_count=2), tuple(scored_track()), 1.5)
    write_scan_json(tmp_path / "clip_scan.json", scan)
    assert repr(read_scan_json(tmp_path / "clip_scan.json")) == repr(scan)   # NaN != NaN
    write_scan_csv(tmp_path / "clip_scan.csv", scan)
    with (tmp_path / "clip_scan.csv").open(newline="") as file:
        rows = list(csv.DictReader(file))
    assert [row["best_rank"] for row in rows] == ["1", "2", "", "", "", ""]
    assert rows[2]["usable"] == "no" and "pitched" in rows[2]["faults"]
    assert rows[0]["gimbal_pitch_deg"] == "" and float(rows[0]["length_m"]) == 2.0


def test_gimbal_pitch_comes_from_the_latest_cue_that_records_it(tmp_path):
    cues = []
    for n, pitch in enumerate([-90.0, -89.5, -60.0], start=1):
        cues.append(f"{n}\n00:00:0{n - 1},000 --> 00:00:0{n},000\n<font size=\"28\">FrameCnt: "
                    f"{n}, DiffTime: 1000ms\n[iso: 100] [rel_alt: 20.000 abs_alt: 25.000] "
                    f"[gb_yaw: 10.0 gb_pitch: {pitch} gb_roll: 0.0] </font>\n")
    path = tmp_path / "clip.SRT"
    path.write_text("\n".join(cues))
    pitch = gimbal_pitch_at(parse_srt(path), np.array([0.0, 0.5, 1.2, 2.7]))
    assert pitch.tolist() == [-90.0, -90.0, -89.5, -60.0]
    path.write_text(cues[0].replace("[gb_yaw: 10.0 gb_pitch: -90.0 gb_roll: 0.0] ", ""))
    assert np.isnan(gimbal_pitch_at(parse_srt(path), np.array([0.5]))).all()


def test_a_short_track_must_keep_its_length_to_be_an_animal():
    """Glitter is seen now and then and changes shape; an animal keeps its length (two of a
    short track's sightings agree within 1.5×)."""
    from dolphinfit.core.scan.scanner import persists

    samples = [0, 10, 20, 30, 40]

    def track(*sightings) -> Track:
        return Track(list(sightings))
    steady = track(seen(0, 100, 100, 200.0), seen(20, 120, 100, 180.0))
    glitter = track(seen(0, 300, 100, 211.0), seen(20, 300, 110, 128.0))  # the sample's
    assert persists(steady, samples) and not persists(glitter, samples)
    long_lived = track(*(seen(t, 100 + t, 100, 200.0 - 2 * t) for t in samples))  # a dive
    assert persists(long_lived, samples)
    once_in_three = track(seen(0, 100, 100), seen(40, 140, 100))  # 2 of the 5 samples
    assert not persists(once_in_three, samples)
    # one sighting cut short (a neighbour took part of its mask): two still agree
    cut_once = track(seen(0, 100, 100, 87.0), seen(10, 110, 100, 78.0), seen(20, 120, 100, 40.0))
    assert persists(cut_once, samples)


def test_an_animal_seen_in_half_the_samples_is_kept_where_it_keeps_its_length():
    """A pair touching, seen in 7 of 14 samples at 154–173 px (the held-out split's echelon
    pair), is an animal; glitter seen as often, its length never the same, is not."""
    from dolphinfit.core.scan.scanner import persists

    samples = list(range(0, 28, 2))
    at = (0, 4, 6, 10, 20, 24, 26)
    steady = Track([seen(t, 100 + t, 100, length)
                    for t, length in zip(at, (159.0, 171.0, 167.0, 165.0, 154.0, 173.0, 171.0))])
    assert persists(steady, samples)
    glitter = Track([seen(t, 300, 100, length)
                     for t, length in zip(at, (40.0, 150.0, 65.0, 210.0, 30.0, 120.0, 90.0))])
    assert not persists(glitter, samples)
