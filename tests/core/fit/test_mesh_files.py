"""A fit's meshes as files (core/fit/mesh_files.py), from the tiny fit of the synthetic clip:
the rest mesh and one posed mesh per fitted frame, each read back with trimesh where the fit
put it."""

import numpy as np
import trimesh

from dolphinfit.core.fit.mesh_files import export_fit_meshes
from dolphinfit.core.model.template import load_template


def _bounds(verts: np.ndarray) -> np.ndarray:
    return np.array([verts.min(axis=0), verts.max(axis=0)])


def _read(path) -> trimesh.Trimesh:
    return trimesh.load(path, force="mesh", process=False)


def test_rest_and_posed_meshes_read_back_where_the_fit_put_them(tiny_run, tmp_path):
    """In every format the rest mesh spans the fitted rest shape and each fitted frame has its
    posed mesh, named by its frame, spanning that frame's posed vertices; a folder exported
    to in several formats keeps each format's posed set."""
    result = tiny_run[0].result
    names = [f"{int(frame):06d}" for frame in result.frame_idx]
    assert len(names) == 8 and len(set(names)) == 8
    for suffix in (".obj", ".ply", ".glb"):
        reports = []
        paths = export_fit_meshes(result, load_template(), tmp_path, suffix, reports.append)
        assert paths == [tmp_path / f"rest_mesh{suffix}",
                         *(tmp_path / "posed" / (name + suffix) for name in names)]
        assert [(r.step, r.total) for r in reports] == [(i, 9) for i in range(1, 10)]
        np.testing.assert_allclose(_read(paths[0]).bounds, _bounds(result.rest_verts),
                                   atol=1e-5, err_msg=suffix)
        for path, verts in zip(paths[1:], result.posed_verts):
            np.testing.assert_allclose(_read(path).bounds, _bounds(verts), atol=1e-5,
                                       err_msg=str(path))
    for suffix in (".obj", ".ply", ".glb"):
        assert len(list((tmp_path / "posed").glob(f"*{suffix}"))) == len(result.frame_idx)
    # PLY keeps the fit's own vertex set, in its order
    np.testing.assert_allclose(_read(tmp_path / "rest_mesh.ply").vertices, result.rest_verts,
                               atol=1e-6)
