"""The 3D viewer under Xvfb + xcb (reference/platform.md §3.3): playback of a posed ellipsoid,
the elliptical solid beside it, toggles, a real screenshot, and no render without a change."""

import numpy as np
import pytest
import trimesh
from PySide6.QtGui import QGuiApplication

from dolphinfit.core.measure.elliptical_solid import elliptical_solid
from dolphinfit.ui.widgets.viewer3d import Viewer3D

LENGTH_M = 2.5
SEMI_AXES_M = (LENGTH_M / 2, 0.25, 0.2)
DEPTH_M = -0.3
SHIFTS_M = np.array([0.0, 1.0, 3.0])  # x translation at each fitted frame
BACKGROUND_RGB = (255, 255, 255)


@pytest.fixture
def animal() -> tuple[np.ndarray, np.ndarray]:
    """(T, V, 3) posed vertices of an ellipsoid 2.5 m long, and its faces."""
    sphere = trimesh.creation.icosphere(subdivisions=2)
    rest = sphere.vertices * SEMI_AXES_M + [0.0, 0.0, DEPTH_M]
    posed = np.stack([rest + [shift, 0.0, 0.0] for shift in SHIFTS_M])
    return posed, np.asarray(sphere.faces)


@pytest.fixture
def viewer(qtbot, qapp, animal) -> Viewer3D:
    if qapp.platformName() != "xcb":
        pytest.skip(f"the 3D view draws only under xcb (Xvfb), not {qapp.platformName()!r}")
    widget = Viewer3D()
    qtbot.addWidget(widget)
    widget.resize(800, 600)
    widget.show()
    qtbot.waitExposed(widget)
    posed, faces = animal
    widget.set_fitted(faces, posed, rest_verts=None)
    return widget


def _points(viewer: Viewer3D, name: str) -> np.ndarray:
    return np.array(viewer.plotter.renderer.actors[name].mapper.dataset.points)


def test_a_fit_shows_its_first_frame_then_the_pose_it_is_given(viewer, animal):
    """The fitted mesh at its first fitted frame, then posed as the fit's motion gives it
    (core.fit.motion), labelled with how that pose was found."""
    posed, _ = animal
    np.testing.assert_allclose(_points(viewer, "posed"), posed[0], atol=1e-6)
    viewer.show_pose(1, posed[0] + [0.5, 0.0, 0.0], "between fitted frames 0 and 2")
    np.testing.assert_allclose(_points(viewer, "posed"), posed[0] + [0.5, 0, 0], atol=1e-6)
    assert viewer.frame_label == "between fitted frames 0 and 2"
    viewer.show_pose(9, posed[2], "nearest fitted frame 4")
    np.testing.assert_allclose(_points(viewer, "posed"), posed[2], atol=1e-6)
    assert viewer.frame_label == "nearest fitted frame 4"


def test_water_plane_toggles(viewer):
    water = viewer.plotter.renderer.actors["water"]
    assert water.GetVisibility()
    assert _points(viewer, "water")[:, 2] == pytest.approx(0.0)
    viewer.toggles["water"].setChecked(False)
    assert not water.GetVisibility()
    viewer.toggles["water"].setChecked(True)
    assert water.GetVisibility()


def test_elliptical_solid_sits_beside_the_animal(viewer, animal):
    widths = np.full(19, 0.5)
    verts, faces = elliptical_solid(LENGTH_M, widths, 0.8 * widths)
    viewer.set_elliptical(verts, faces)
    meshes = [name for name in ("posed", "rest", "elliptical")
              if name in viewer.plotter.renderer.actors]
    assert meshes == ["posed", "elliptical"]
    solid = _points(viewer, "elliptical")
    posed, _ = animal
    lo, hi = posed.reshape(-1, 3).min(0), posed.reshape(-1, 3).max(0)
    centre = (lo + hi) / 2
    np.testing.assert_allclose(solid.min(0), [centre[0] - LENGTH_M / 2, hi[1] + 0.25,
                                              centre[2] - 0.2], atol=1e-6)
    np.testing.assert_allclose(solid.max(0), [centre[0] + LENGTH_M / 2, hi[1] + 0.75,
                                              centre[2] + 0.2], atol=1e-6)
    viewer.set_elliptical(None)
    assert "elliptical" not in viewer.plotter.renderer.actors


def test_screenshot_shows_the_scene(viewer):
    image = viewer.plotter.screenshot(return_img=True)
    drawn = np.any(image[..., :3] != BACKGROUND_RGB, axis=-1)
    assert drawn.mean() > 0.01


def test_a_tall_narrow_dock_keeps_the_whole_scene_across(viewer, qtbot):
    """Placed at 800 × 600, then resized to a column 300 × 900 (the 3D view's tab beside
    the results): the scene's drawn pixels still stop short of the left and right edges."""
    viewer.resize(300, 900)
    qtbot.waitUntil(lambda: viewer.plotter.window_size[0] <= 300, timeout=5_000)
    viewer.plotter.render()
    image = viewer.plotter.screenshot(return_img=True)
    columns = np.flatnonzero(np.any(image[..., :3] != BACKGROUND_RGB, axis=(0, 2)))
    assert columns.min() > 0 and columns.max() < image.shape[1] - 1


def test_nothing_renders_without_a_change(viewer, qtbot, monkeypatch):
    qtbot.wait(200)  # let the exposure's paints finish
    calls, vtk_renders = [], []
    render = viewer.plotter.render
    monkeypatch.setattr(viewer.plotter, "render", lambda: calls.append(1) or render())
    observer = viewer.plotter.ren_win.AddObserver("EndEvent", lambda *_: vtk_renders.append(1))
    try:
        qtbot.wait(500)
        assert (calls, vtk_renders) == ([], [])
        viewer.show_pose(1, _points(viewer, "posed") + [0.1, 0.0, 0.0], "a test pose")
        qtbot.wait(50)
        assert calls and vtk_renders
    finally:
        viewer.plotter.ren_win.RemoveObserver(observer)


def test_clear_and_close_release_the_view(viewer):
    viewer.clear()
    assert not {"posed", "water"} & set(viewer.plotter.renderer.actors)
    viewer.close_viewer()
    assert viewer.plotter is None
    viewer.show_pose(3, np.zeros((3, 3)), "a test pose")  # a no-op once closed


def test_headless_platform_shows_a_label(qtbot, monkeypatch):
    monkeypatch.setattr(QGuiApplication, "platformName", staticmethod(lambda: "offscreen"))
    widget = Viewer3D()
    qtbot.addWidget(widget)
    assert widget.plotter is None
    widget.show_pose(1, np.zeros((3, 3)), "a test pose")
    widget.set_elliptical(None)
