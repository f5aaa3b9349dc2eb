"""The procedural template asset: regeneration, topology, anatomy, skinning, UVs, albedo."""

import numpy as np
import pytest
import trimesh

from dolphinfit.core.errors import InputError
from dolphinfit.core.model.body import RING_SIZE, body_faces, build_body, ring_angles_deg
from dolphinfit.core.model.builder import TEMPLATE_LENGTH_M, build_template
from dolphinfit.core.model.fins import DORSAL_FIN, FLUKE
from dolphinfit.core.model.profile import ring_fractions
from dolphinfit.core.model.skeleton import ROOT_T
from dolphinfit.core.model.summary import shape_targets, summarize
from dolphinfit.core.model.template import (
    FORMAT_VERSION, TEMPLATE_PATH, load_template, save_template,
)
from dolphinfit.core.model.texture import body_uv


@pytest.fixture(scope="module")
def template():
    return load_template()


def test_regenerated_template_matches_committed_asset(template):
    """`template build` reproduces the committed asset, array by array."""
    fresh = build_template()
    for name in ("verts", "uvs", "skin_weights", "rest_joints", "joint_axes"):
        np.testing.assert_allclose(getattr(fresh, name), getattr(template, name),
                                   rtol=0, atol=1e-12, err_msg=name)
    for name in ("faces", "face_uvs_idx", "joint_parents", "joint_group", "joint_mirror",
                 "station_rings"):
        np.testing.assert_array_equal(getattr(fresh, name), getattr(template, name), name)
    assert np.abs(fresh.albedo.astype(int) - template.albedo).max() <= 1
    assert fresh.joint_names == template.joint_names
    assert fresh.group_names == template.group_names
    for joint in fresh.fin_vertices:
        np.testing.assert_array_equal(fresh.fin_vertices[joint], template.fin_vertices[joint])


def test_save_is_deterministic(tmp_path):
    """Saving the same template twice gives identical bytes."""
    fresh = build_template()
    save_template(fresh, tmp_path / "a.npz")
    save_template(fresh, tmp_path / "b.npz")
    assert (tmp_path / "a.npz").read_bytes() == (tmp_path / "b.npz").read_bytes()


def test_template_is_one_closed_consistently_wound_manifold(template):
    """Watertight, consistently wound, outward, genus 0, no degenerate or repeated faces."""
    mesh = trimesh.Trimesh(template.verts, template.faces, process=False)
    assert mesh.is_watertight and mesh.is_winding_consistent and mesh.is_volume
    assert mesh.volume > 0
    assert mesh.euler_number == 2
    assert len(mesh.split(only_watertight=False)) == 1
    assert mesh.area_faces.min() > 1e-8
    assert len(np.unique(np.sort(template.faces, axis=1), axis=0)) == len(template.faces)
    assert 2000 <= len(template.faces) <= 10000


def test_anatomical_targets_are_met(template):
    """Volume/BL³, width profile, HW trend and fin placement lie within their targets."""
    summary = summarize(template)
    failed = [(c.name, c.value) for c in shape_targets(summary) if not c.ok]
    assert failed == []
    assert summary.length_m == pytest.approx(TEMPLATE_LENGTH_M, abs=1e-12)


def test_orientation_rostrum_plus_x_dorsal_plus_z(template):
    """Rostrum tip is the foremost point, the dorsal fin the highest, the root at the origin."""
    verts = template.verts
    assert verts[template.rostrum_idx, 0] == pytest.approx(verts[:, 0].max())
    assert verts[template.rostrum_idx, 0] - verts[template.notch_idx, 0] == pytest.approx(2.6)
    assert np.argmax(verts[:, 2]) in set(template.fin_vertices["dorsal_fin"].tolist())
    np.testing.assert_allclose(template.rest_joints[0], 0.0, atol=1e-12)
    assert template.verts[template.fin_vertices["fluke_l"], 1].min() > 0
    assert template.verts[template.fin_vertices["fluke_r"], 1].max() < 0


def test_template_is_mirror_symmetric(template):
    """Every vertex has a twin mirrored across the sagittal plane (y → −y)."""
    mirrored = template.verts * np.array([1.0, -1.0, 1.0])
    distance, _ = trimesh.proximity.ProximityQuery(
        trimesh.Trimesh(template.verts, template.faces, process=False)).vertex(mirrored)
    assert distance.max() < 1e-9


def test_fins_stay_outside_the_body(template):
    """No fin vertex above its base lies inside the closed body tube."""
    rows_t = ring_fractions()
    tube = build_body(rows_t, ring_angles_deg(rows_t, DORSAL_FIN.attachment, FLUKE.attachment),
                      TEMPLATE_LENGTH_M, ROOT_T)
    body = trimesh.Trimesh(tube.verts, body_faces(tube, set())[0], process=False)
    assert body.is_watertight
    fin_verts = np.concatenate(list(template.fin_vertices.values()))
    assert not body.contains(template.verts[fin_verts]).any()


def test_skeleton_chain_and_parts(template):
    """Spine chain rostrum→fluke root with ≥ 4 tail-stock joints; symmetric fins share parts."""
    names = template.joint_names
    parents = template.joint_parents
    chain, j = [], names.index("tail4")
    while j >= 0:
        chain.append(names[j])
        j = parents[j]
    assert chain[::-1] == ["root", "tail0", "tail1", "tail2", "tail3", "tail4"]
    assert names[parents[names.index("head")]] == "thorax"
    assert all(p < j for j, p in enumerate(parents) if p >= 0)
    groups = template.joint_group
    assert groups[names.index("flipper_l")] == groups[names.index("flipper_r")]
    assert groups[names.index("fluke_l")] == groups[names.index("fluke_r")]
    assert template.joint_mirror[names.index("flipper_r")]
    assert template.group_names[0] == "root" and groups[0] == 0
    assert len(template.group_names) < len(names)


def test_skin_weights_are_a_smooth_partition_of_unity(template):
    """Weights are non-negative, sum to one, and change gradually between adjacent rings."""
    weights = template.skin_weights
    assert weights.min() >= 0.0
    np.testing.assert_allclose(weights.sum(axis=1), 1.0, atol=1e-12)
    ring_weights = weights[1:1 + len(ring_fractions()) * RING_SIZE:RING_SIZE]
    assert np.abs(np.diff(ring_weights, axis=0)).max() < 0.6
    fin_tip = template.fin_vertices["fluke_l"][-1]
    assert weights[fin_tip, template.joint_names.index("fluke_l")] == pytest.approx(1.0)


def test_station_rings_lie_on_the_body_at_the_stations(template):
    """Each of the 19 rings is a full body ring at its station, with no fin vertex in it."""
    rings = template.station_rings
    assert rings.shape == (19, RING_SIZE)
    x_rostrum = template.verts[template.rostrum_idx, 0]
    t = (x_rostrum - template.verts[rings, 0]) / template.length_m
    np.testing.assert_allclose(t, np.broadcast_to(template.station_fractions[:, None], t.shape),
                               atol=1e-12)
    fin_verts = np.concatenate(list(template.fin_vertices.values()))
    assert not np.isin(rings, fin_verts).any()


def test_uv_map_and_countershaded_albedo(template):
    """UVs stay in the unit square; the back is darker than the flanks, the flanks than the belly."""
    assert template.albedo.shape == (512, 512) and template.albedo.dtype == np.uint8
    assert template.face_uvs_idx.shape == template.faces.shape
    assert template.uvs.min() >= 0.0 and template.uvs.max() <= 1.0

    def luma(t, phi):
        u, v = body_uv(np.array(t), np.array(phi))
        return template.albedo[int(v * 512), int(u * 512)]

    back, flank, belly = luma(0.4, 0.0), luma(0.4, 100.0), luma(0.4, 175.0)
    assert back + 40 < flank and flank + 40 < belly


def test_loading_a_bad_asset_raises_input_error(tmp_path):
    """A file that is not a template, or of another format version, is refused by name."""
    bogus = tmp_path / "bogus.npz"
    bogus.write_text("not a zip")
    with pytest.raises(InputError, match="bogus.npz"):
        load_template(bogus)
    with pytest.raises(InputError, match="not found"):
        load_template(tmp_path / "missing.npz")
    assert TEMPLATE_PATH.name == f"dolphin_template_v{FORMAT_VERSION}.npz"
