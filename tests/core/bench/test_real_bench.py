"""``dolphinfit bench real`` on the shipped real data: the MedidoR replay to the hundredth of
a pixel, the data sets as their sources describe them, the outline geometry on analytic
shapes and on real outlines, and the command."""

import json

import cv2
import numpy as np
import pytest

from dolphinfit.app.cli import main
from dolphinfit.core.bench.real_bench import (
    edge_point_offsets, minke_figures, outline_scores, replay_medidor, right_whale_figures,
    score_outline,
)
from dolphinfit.core.bench.real_data import (
    OUTLINE_PAIRS, crossings, distance_to_outline, load_medidor, load_minke, load_outlines,
    real_data_dir,
)
from dolphinfit.core.bench.real_fit import fit_minke
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.segment.backends import DEFAULT_BACKEND


def test_medidor_clicks_through_its_geometry_give_its_sheet_to_a_hundredth_of_a_pixel():
    """The 3 length clicks and 9 width pairs of MedidoR's GUI test: length and widths equal
    the spreadsheet it wrote; our own geometry (spline, perpendicular) differs by 0.65 px."""
    score = replay_medidor(load_medidor())
    assert score.max_abs_difference_px < 0.01
    assert score.length_px == pytest.approx(1171.55663356342, abs=0.01)
    assert score.default_max_abs_difference_px == pytest.approx(0.652, abs=0.001)


def test_the_data_sets_are_what_their_sources_say():
    """Minke: two people, 7.593 m with 19 widths and 7.547 m with 9, at 3.178 mm/px;
    MedidoR: 23 clicks; outlines: 639, of which 99 cannot be scored: one with a point outside
    its image, 96 that cross themselves (most across the head), two whose rostrum point lies
    off the outline."""
    minke = load_minke()
    assert [h.length_m for h in minke.humans] == [7.593, 7.547]
    assert [len(h.widths_m) for h in minke.humans] == [19, 9]
    assert minke.calibration.m_per_px == pytest.approx(28.4 * 0.00391667 / 35, rel=1e-6)
    medidor = load_medidor()
    np.testing.assert_allclose(medidor.length_clicks_px[0], [775.4, 810.9])
    np.testing.assert_allclose(medidor.fluke_clicks_px[1], [2045.1, 1055.9])
    outlines = load_outlines()
    assert outlines.outlines.shape == (639, 2, 301)
    reasons = [why for _, why in outlines.left_out]
    assert (reasons.count("outline points outside the image"),
            reasons.count("the outline crosses itself"),
            reasons.count("the rostrum point lies off the outline")) == (1, 96, 2)
    assert (144, "outline points outside the image") in outlines.left_out


def test_crossings_and_distances_of_outlines():
    """A square has no crossing; a figure of eight has one; a point's distance to an
    outline is to its nearest segment."""
    square = np.array([[0.0, 10, 10, 0], [0, 0, 10, 10]])
    eight = np.array([[0.0, 10, 10, 0], [0, 10, 0, 10]])
    assert (crossings(square), crossings(eight)) == (0, 1)
    assert distance_to_outline(np.array([5.0, -3.0]), square) == pytest.approx(3.0)
    assert distance_to_outline(np.array([13.0, 14.0]), square) == pytest.approx(5.0)


def test_a_folder_without_the_data_is_refused(tmp_path):
    with pytest.raises(InputError, match="no real data sets here"):
        real_data_dir(tmp_path)


def test_edge_point_offsets_along_each_pair_on_a_disc():
    """A disc of radius 50: points clicked at radius 40 lie 10 px inside the outline (+10),
    points at radius 55 5 px outside it (−5), whatever the pair's direction."""
    mask = np.zeros((201, 201), np.uint8)
    cv2.circle(mask, (100, 100), 50, 1, -1)
    centre = np.array([100.0, 100.0])
    directions = np.array([[1.0, 0.0], [0.6, 0.8]])
    for radius, expected in ((40.0, 10.0), (55.0, -5.0)):
        offsets = edge_point_offsets(mask.astype(bool), centre - radius * directions,
                                     centre + radius * directions)
        np.testing.assert_allclose(offsets, expected, atol=0.6)


def _ellipse_outline(a: float, b: float, points: int = 301) -> np.ndarray:
    angle = np.linspace(0, 2 * np.pi, points)
    return np.stack([600 + a * np.cos(angle), 400 + b * np.sin(angle)])


def test_an_ellipse_scores_its_own_widths():
    """An ellipse 800 × 160 px with the hand pairs placed on it across the body: our widths
    at those stations equal the people's within a pixel and the midline's ends lie at the
    tips; the tips are told apart only by where the rostrum point is."""
    outline = _ellipse_outline(400.0, 80.0)
    xs = np.linspace(-300, 300, len(OUTLINE_PAIRS))
    half = 80.0 * np.sqrt(1 - (xs / 400.0) ** 2)
    points = {"rostrum": np.array([1000.0, 400.0]), "peduncle": np.array([200.0, 400.0])}
    for x, h, pair in zip(xs, half, OUTLINE_PAIRS):
        points[f"side1_{pair}"] = np.array([600 + x, 400 - h])
        points[f"side2_{pair}"] = np.array([600 + x, 400 + h])
    score = score_outline(outline, points)
    np.testing.assert_allclose(score["ours_px"], score["human_px"], atol=1.0)
    np.testing.assert_allclose(score["outline_px"], score["human_px"], atol=1.0)
    assert score["rostrum_px"] < 3 and score["peduncle_px"] < 3


def test_real_outlines_body_widths_agree_with_the_outline():
    """On the first 40 real outlines, our widths at the pairs across the widest part of the
    body lie within 1.5 px (median) of the outline's own width along the person's line."""
    figures = outline_scores(load_outlines(), limit=40)
    assert figures["outlines"] == 40
    for pair in ("eye", "body1", "body2"):
        assert figures["pairs"][pair]["ours_vs_outline"]["median_px"] < 1.5


def test_bench_real_command_prints_the_parts_asked_for(capsys):
    assert main(["bench", "real", "--parts", "replay,outlines", "--outlines", "5",
                 "--json"]) == 0
    figures = json.loads(capsys.readouterr().out)
    assert set(figures) == {"medidor_replay", "outlines", "run"}
    assert figures["outlines"]["outlines"] == 5
    assert figures["run"]["options"]["parts"] == "replay,outlines"
    assert main(["bench", "real", "--parts", "replay,outlines", "--outlines", "5"]) == 0
    out = capsys.readouterr().out
    assert "largest difference of length and 9 widths" in out
    assert "Whale outlines with hand points (5 outlines" in out and "peduncle_width" in out
    assert main(["bench", "real", "--parts", "fitting"]) == 2
    assert "--parts" in capsys.readouterr().err


def test_a_click_on_the_minke_measures_it_near_the_two_people():
    """A click on the minke's back: the whole whale, flukes included, is found (at a working
    scale: it is longer than the frame is high); its suggested length lies within 3 % of the
    people's mean (they differ by 0.6 %) and its widths within 5 % (median) of theirs."""
    minke = load_minke()
    figures = minke_figures(minke, ("click",), DEFAULT_BACKEND, lambda line: None)
    click = figures["seeds"]["click"]
    assert click["error"] == ""
    assert abs(click["length_error_share"]) < 0.03
    assert click["median_width_error_share"] < 0.05


def test_the_automatic_seed_takes_the_right_whale_not_the_caption():
    """The right whale frame carries a burned-in caption, salient and elongated: the
    automatic seed takes the whale (its mask's length within 10 % of the clicked one)."""
    medidor = load_medidor()
    figures = right_whale_figures(medidor, ("auto",), DEFAULT_BACKEND, lambda line: None)
    auto = figures["seeds"]["auto"]
    assert auto["error"] == ""
    assert auto["length_px"] == pytest.approx(medidor.sheet.length_px, rel=0.1)
    assert auto["offsets_found"] == 18


def test_the_fit_part_fits_the_minke_and_scores_it_against_both_people():
    """The fit part on the minke still, a quick fit at 720 px wide (the default takes
    minutes): a fit that runs to its end, unreliable for the one reason that a still is a
    single frame, whose length lies within 10 % of each person's and whose interval is
    ordered around it, with one entry per person."""
    minke = load_minke()
    quick = FitConfig(heading_trial_steps=4, steps_global=10, steps_body=10, steps_shape=20,
                      use_roi=False)
    fit = fit_minke(minke, DEFAULT_BACKEND, quick)
    assert fit["status"] == "unreliable" and fit["mean_iou"] > 0.85
    assert [reason.split(" (")[0] for reason in fit["reasons"]] == ["only 1 frame(s) fitted"]
    low, high = fit["interval"]["length_m"]["low"], fit["interval"]["length_m"]["high"]
    assert low < fit["length_m"] < high
    assert [p["source"] for p in fit["people"]] == [h.source for h in minke.humans]
    for person in fit["people"]:
        assert abs(person["length_error_share"]) < 0.1
        assert person["length_in_interval"] == (low <= person["length_m"] <= high)
        assert person["median_width_error_share"] < 0.15
