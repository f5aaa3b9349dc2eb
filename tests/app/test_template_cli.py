"""`dolphinfit template build | info | export` driven through app.cli.main."""

import json

import numpy as np
import pytest
import trimesh

from dolphinfit.app.cli import main
from dolphinfit.core.model.template import load_template


def test_info_json_reports_figures_and_stations(capsys):
    """`template info --json` prints one object with length, volume, watertightness, stations."""
    assert main(["template", "info", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["length_m"] == pytest.approx(2.6)
    assert 0.011 <= info["volume_m3"] / 2.6**3 <= 0.015
    assert info["watertight"] is True
    assert len(info["stations"]) == 19
    assert info["stations"][0]["fraction"] == pytest.approx(0.05)
    assert info["num_joints"] == 13 and info["num_groups"] == 11


def test_info_text_lists_targets(capsys):
    """The text report ends with the anatomical targets, all met."""
    assert main(["template", "info"]) == 0
    out = capsys.readouterr().out
    assert "volume / BL³" in out and "fluke span / BL" in out
    assert " NO" not in out


def test_build_writes_a_loadable_asset(tmp_path, capsys):
    """`template build --out` writes an asset equal to the bundled one."""
    out = tmp_path / "template.npz"
    assert main(["template", "build", "--out", str(out)]) == 0
    built, bundled = load_template(out), load_template()
    np.testing.assert_allclose(built.verts, bundled.verts, atol=1e-12)
    np.testing.assert_array_equal(built.faces, bundled.faces)


@pytest.mark.parametrize("suffix", [".ply", ".obj", ".glb"])
def test_export_round_trips_through_trimesh(tmp_path, suffix):
    """Each format reloads with the template's geometry and a closed surface."""
    out = tmp_path / f"dolphin{suffix}"
    assert main(["template", "export", str(out)]) == 0
    mesh = trimesh.load(out, force="mesh", process=False)
    template = load_template()
    merged = mesh.copy()
    merged.merge_vertices(merge_tex=True, merge_norm=True)
    assert merged.is_watertight
    assert mesh.volume == pytest.approx(trimesh.Trimesh(template.verts, template.faces).volume,
                                        rel=1e-6)
    np.testing.assert_allclose(mesh.bounds, np.stack([template.verts.min(0),
                                                      template.verts.max(0)]), atol=1e-6)


def test_textured_export_keeps_countershading(tmp_path):
    """In the GLB the back is dark and the belly light at mid-body."""
    out = tmp_path / "dolphin.glb"
    assert main(["template", "export", str(out)]) == 0
    mesh = trimesh.load(out, force="mesh")
    grey = mesh.visual.to_color().vertex_colors[:, 0].astype(float)
    mid = np.abs(mesh.vertices[:, 0]) < 0.05
    top = grey[mid][np.argmax(mesh.vertices[mid, 2])]
    bottom = grey[mid][np.argmin(mesh.vertices[mid, 2])]
    assert top < 90 and bottom > 190


def test_export_shaped_and_posed(tmp_path):
    """--length rescales to that body length; --pose bends the tail stock."""
    straight, bent = tmp_path / "straight.ply", tmp_path / "bent.ply"
    assert main(["template", "export", str(straight), "--length", "2.2"]) == 0
    assert main(["template", "export", str(bent), "--length", "2.2",
                 "--pose", "tail2=0,25,0"]) == 0
    template = load_template()
    a = trimesh.load(straight, process=False).vertices
    b = trimesh.load(bent, process=False).vertices
    assert np.linalg.norm(a[template.rostrum_idx] - a[template.notch_idx]) == pytest.approx(2.2)
    assert abs(b[template.notch_idx, 2] - a[template.notch_idx, 2]) > 0.1
    np.testing.assert_allclose(a[template.rostrum_idx], b[template.rostrum_idx], atol=1e-9)


@pytest.mark.parametrize("argv, message", [
    (["--pose", "fins=0,0,1"], "unknown part 'fins'"),
    (["--shape", "head=0.1,0.2"], "expected 4 comma-separated numbers"),
    (["--length", "-1"], "--length: -1 m is outside the plausible range 0.5–35 m"),
])
def test_export_bad_options_exit_2(tmp_path, capsys, argv, message):
    """Bad part names, value counts or lengths give exit code 2 and say what is wrong."""
    assert main(["template", "export", str(tmp_path / "x.ply"), *argv]) == 2
    assert message in capsys.readouterr().err


def test_export_unknown_format_exit_2(tmp_path, capsys):
    """An unsupported suffix is refused with the list of formats."""
    assert main(["template", "export", str(tmp_path / "x.stl")]) == 2
    assert ".ply, .obj, .glb" in capsys.readouterr().err
