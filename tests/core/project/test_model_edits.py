"""The project tree and the measurement edits: pure values, geometry that follows the midline."""

import numpy as np
import pytest

from dolphinfit.core.measure.annotation import pixel_measurements
from dolphinfit.core.project import edits
from dolphinfit.core.project.model import (
    Animal, Measurement, MeasurementKey, add_measurement, get_measurement, next_animal_id,
    remove_measurement, with_measurement,
)

from .conftest import SEMI_MAJOR, SEMI_MINOR, ellipse_measurement


def test_ellipse_measurement_gives_its_analytic_length_and_widths():
    pixels = pixel_measurements(ellipse_measurement().to_annotation())
    assert pixels.length_px == pytest.approx(2 * SEMI_MAJOR, rel=1e-9)
    fractions = np.arange(1, 20) * 0.05
    expected = 2 * SEMI_MINOR * np.sqrt(1 - (2 * fractions - 1) ** 2)
    np.testing.assert_allclose(pixels.widths_px, expected, rtol=1e-9)


def test_edits_build_new_values_and_leave_the_old_one_alone():
    m = Measurement(frame_idx=0)
    m1 = edits.add_midline_point(m, 10, 20)
    m2 = edits.add_midline_point(m1, 110, 20)
    assert len(m.midline_px) == 0 and len(m1.midline_px) == 1 and m2.has_length
    with pytest.raises(ValueError):
        edits.add_midline_point(m2, 110, 20)  # same as the last click
    m3 = edits.insert_midline_point(m2, edits.nearest_segment(m2, 60, 25), 60, 25)
    np.testing.assert_array_equal(m3.midline_px[1], [60, 25])
    assert edits.delete_midline_point(m3, 1).midline_px.tolist() == m2.midline_px.tolist()
    with pytest.raises(ValueError):
        m3.midline_px[0, 0] = 5.0  # read-only arrays: the tree cannot change under undo


def test_handles_follow_the_midline_when_it_moves():
    m = ellipse_measurement()
    moved = edits.move_midline_point(edits.move_midline_point(
        edits.move_midline_point(m, 0, *(m.midline_px[0] + 30)), 1, *(m.midline_px[1] + 30)),
        2, *(m.midline_px[2] + 30))
    before = pixel_measurements(m.to_annotation()).widths_px
    after = pixel_measurements(moved.to_annotation()).widths_px
    np.testing.assert_allclose(after, before, rtol=1e-9)


def test_reversing_keeps_every_edge_and_width_in_place():
    m = edits.set_skipped(edits.set_mirror_side(ellipse_measurement(), None), 4, True)
    r = edits.reverse_midline(m)
    a, b = m.to_annotation(), r.to_annotation()
    np.testing.assert_allclose(b.edges_px[::-1, ::-1], a.edges_px, atol=1e-9, equal_nan=True)
    np.testing.assert_allclose(pixel_measurements(b).widths_px[::-1],
                               pixel_measurements(a).widths_px, rtol=1e-9, equal_nan=True)
    assert r.skipped[14] and not r.skipped[4]
    assert edits.reverse_midline(edits.set_mirror_side(m, "A")).mirror_side == "B"


def test_offset_of_point_projects_on_the_perpendicular_and_skip_keeps_handles():
    m = ellipse_measurement()
    stations = edits.stations_of(m)
    point = stations.points_px[9] + 40 * stations.normals[9] + 15 * np.array(
        [stations.normals[9][1], -stations.normals[9][0]])  # off the line along the body
    assert edits.offset_of_point(stations, 9, *point) == pytest.approx(40.0)
    skipped = edits.set_skipped(m, 9, True)
    assert np.isnan(pixel_measurements(skipped.to_annotation()).widths_px[9])
    assert skipped.is_station_done()[9]
    restored = edits.set_offset(skipped, 9, 0, 41.0)
    assert not restored.skipped[9] and restored.offsets_px[9, 0] == 41.0


def test_mirror_side_doubles_one_side():
    m = edits.set_offset(ellipse_measurement(), 9, 1, np.nan)
    assert not m.is_station_done()[9]
    mirrored = edits.set_mirror_side(m, "A")
    assert mirrored.is_station_done()[9]
    width = pixel_measurements(mirrored.to_annotation()).widths_px[9]
    assert width == pytest.approx(2 * m.offsets_px[9, 0])


def test_offsets_from_edges_fills_only_missing_edges():
    m = ellipse_measurement()
    stations = edits.stations_of(m)
    gap = edits.set_offset(m, 2, 0, np.nan)
    edges = stations.points_px[:, None, :] + np.full((19, 2, 1), 10.0) * stations.normals[:, None]
    filled = edits.offsets_from_edges(gap, edges)
    assert filled.offsets_px[2, 0] == pytest.approx(10.0)
    np.testing.assert_array_equal(np.delete(filled.offsets_px, 2, 0), np.delete(m.offsets_px, 2, 0))


def test_tree_edits_share_untouched_branches(project):
    key = MeasurementKey(0, 0, 1)
    changed = with_measurement(project, key, edits.set_skipped(get_measurement(project, key),
                                                               0, True))
    assert changed.clips[0].animals[1] is project.clips[0].animals[1]
    assert get_measurement(changed, MeasurementKey(0, 0, 0)) is get_measurement(
        project, MeasurementKey(0, 0, 0))
    added, new_key = add_measurement(project, 0, 0, Measurement(frame_idx=5))
    assert new_key == MeasurementKey(0, 0, 1)  # kept in frame order: 3, 5, 7
    assert [m.frame_idx for m in added.clips[0].animals[0].measurements] == [3, 5, 7]
    with pytest.raises(ValueError):
        add_measurement(project, 0, 0, Measurement(frame_idx=3))
    assert len(remove_measurement(added, new_key).clips[0].animals[0].measurements) == 2
    assert next_animal_id(project.clips[0]) == "dolphin 3"
    assert Animal("x").measurement_at(0) is None


def test_fit_settings_make_the_engines_configuration():
    from dolphinfit.core.fit.config import FitConfig
    from dolphinfit.core.project.fit_settings import FitSettings, fit_config, fit_dir

    base = FitConfig()
    quick = fit_config(FitSettings(start_s=1.0, end_s=3.0, fps=2.5, quality="quick",
                                   refraction=True, roi=False))
    assert (quick.steps_shape, quick.steps_global) == (base.steps_shape // 2,
                                                       base.steps_global // 2)
    # the coarse steps and the shape's final steps on every frame keep their share of the steps
    assert (quick.coarse_steps, quick.shape_full_steps) == (base.coarse_steps // 2,
                                                            base.shape_full_steps // 2)
    assert (quick.start_s, quick.end_s, quick.fps) == (1.0, 3.0, 2.5)
    assert quick.use_refraction and not quick.use_roi
    assert fit_config(FitSettings()).steps_shape == base.steps_shape
    for bad in ({"quality": "best"}, {"fps": 0.0}, {"start_s": 2.0, "end_s": 1.0}):
        with pytest.raises(ValueError):
            FitSettings(**bad)
    from pathlib import Path
    folder = fit_dir(Path("/d/survey.dolphinfit"), "a/DJI_1.MP4", "dolphin 1")
    assert folder.parent == Path("/d/survey.fits")
    assert folder.name.startswith("DJI_1-") and folder.name.endswith("_dolphin-1")
    assert fit_dir(Path("/d/survey.dolphinfit"), "b/DJI_1.MP4", "dolphin 1") != folder


def test_edge_sources_follow_suggest_move_and_click():
    """Suggested edges stay suggested until moved; a click makes an edge clicked."""
    m = edits.set_offset(edits.set_offset(ellipse_measurement(), 2, 0, np.nan), 5, 1, np.nan)
    assert (m.edge_sources[np.isfinite(m.offsets_px)] == "clicked").all()
    assert m.edge_sources[2, 0] == m.edge_sources[5, 1] == ""
    stations = edits.stations_of(m)
    edges = stations.points_px[:, None, :] + np.full((19, 2, 1), 10.0) * stations.normals[:, None]
    suggested = edits.offsets_from_edges(m, edges)
    assert suggested.edge_sources[2, 0] == suggested.edge_sources[5, 1] == "suggested"
    assert (np.delete(suggested.edge_sources.ravel(), [2 * 2, 5 * 2 + 1]) == "clicked").all()
    everything = edits.offsets_from_edges(m, edges, only_missing=False)
    assert (everything.edge_sources == "suggested").all()
    moved = edits.move_offset(edits.move_offset(everything, 2, 0, 12.0), 2, 0, 13.0)
    assert moved.edge_sources[2, 0] == "suggested_moved" and moved.offsets_px[2, 0] == 13.0
    assert edits.move_offset(m, 3, 0, 40.0).edge_sources[3, 0] == "clicked"
    clicked = edits.set_offset(moved, 4, 1, -11.0)
    assert clicked.edge_sources[4, 1] == "clicked"
    assert edits.set_offset(clicked, 2, 0, np.nan).edge_sources[2, 0] == ""
    reversed_ = edits.reverse_midline(clicked)
    assert reversed_.edge_sources[18 - 2, 1] == "suggested_moved"
    assert reversed_.edge_sources[18 - 4, 0] == "clicked"


def test_used_edge_sources_leave_out_edges_no_width_uses():
    """Skipped stations, half-placed stations and the side a mirror leaves out have none."""
    m = edits.set_skipped(edits.set_offset(ellipse_measurement(), 3, 1, np.nan), 7, True)
    used = m.used_edge_sources()
    assert (used[[3, 7]] == "").all() and (np.delete(used, [3, 7], axis=0) == "clicked").all()
    assert (edits.set_mirror_side(m, "B").used_edge_sources()[:, 0] == "").all()


def test_bad_edge_source_is_refused():
    with pytest.raises(ValueError, match="edge sources"):
        Measurement(frame_idx=0, edge_sources=np.full((19, 2), "guessed"))
