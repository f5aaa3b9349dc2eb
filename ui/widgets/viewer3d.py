"""The 3D view of a fit: the posed mesh at the current clip frame, the rest-pose mesh and the
elliptical solid beside it, the water plane, the camera's view direction and a 1 m scale bar.

Layout (world frame, metres, z up, water at z = 0): the posed mesh sits where the fit put it.
Beside it, towards +y, come the rest-pose mesh and then the elliptical solid, each centred in
x and z on the posed mesh's box over all fitted frames: the first centred one width W beyond
that box, the next 1.5·W further, W being the wider of the two.

The view renders only after a change (no auto-update timer). Under the "offscreen" Qt platform
(no display: QOpenGLWidget cannot draw, reference/platform.md §3.3) a label stands in for it.
"""

import numpy as np
import pyvista as pv
from PySide6.QtGui import QCloseEvent, QGuiApplication
from PySide6.QtWidgets import QCheckBox, QGridLayout, QLabel, QPushButton, QVBoxLayout, QWidget
from pyvistaqt import QtInteractor

SPACING = 1.5          # centre-to-centre spacing of side-by-side bodies, × the wider width
WATER_MARGIN = 0.25    # water plane margin around the bodies, × body length
ARROW_HEIGHT = 0.5     # camera arrow start above the animal's top, × body length
ARROW_LENGTH = 0.3     # × body length
SCALE_BAR_M = 1.0
BACKGROUND = "white"
# toggle key → (checkbox text, its tooltip, actor names it shows or hides); short texts in
# two rows keep the dock narrow enough to leave the video half the window
TOGGLES = {
    "fitted": ("Fit", "the fitted mesh, posed at the frame shown", ("posed", "rest")),
    "elliptical": ("Elliptical", "the elliptical method's solid", ("elliptical",)),
    "water": ("Water", "the water surface (z = 0 m)", ("water",)),
    "camera": ("Camera", "the direction the camera looks from", ("camera",)),
    "scale": (f"{SCALE_BAR_M:g} m bar", f"a scale bar {SCALE_BAR_M:g} m long",
              ("scale_bar", "scale_label")),
}
TOOLBAR_COLUMNS = 3


def _bounds(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper corner of the axis-aligned box around (..., 3) points."""
    flat = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    return flat.min(axis=0), flat.max(axis=0)


def _centred_at(verts: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """(V, 3) vertices moved so that their box centre is ``centre``."""
    lo, hi = _bounds(verts)
    return verts + (centre - (lo + hi) / 2.0)


class Viewer3D(QWidget):
    """The 3D view with its toolbar of toggles; ``plotter`` is None when it cannot draw."""

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        self.plotter: QtInteractor | None = None
        self.toggles: dict[str, QCheckBox] = {}
        self.frame_label = ""
        self._fit: tuple[np.ndarray, np.ndarray] | None = None  # posed (T, V, 3), faces
        self._rest: np.ndarray | None = None
        self._solid: tuple[np.ndarray, np.ndarray] | None = None
        self._posed_mesh: pv.PolyData | None = None
        if QGuiApplication.platformName() == "offscreen":
            layout.addWidget(QLabel("The 3D view needs a display (Qt platform: offscreen)."))
            return
        layout.addLayout(self._build_toolbar())
        self.plotter = QtInteractor(self, off_screen=False, auto_update=False)
        self.plotter.set_background(BACKGROUND)
        self._label_actor = self.plotter.add_text("", position="upper_left", font_size=10,
                                                  color="black", name="frame_label",
                                                  render=False)
        layout.addWidget(self.plotter, stretch=1)

    def _build_toolbar(self) -> QGridLayout:
        bar = QGridLayout()
        for i, (key, (text, tip, _)) in enumerate(TOGGLES.items()):
            box = QCheckBox(text)
            box.setToolTip(f"Show {tip}")
            box.setChecked(True)
            box.toggled.connect(self._on_toggled)
            self.toggles[key] = box
            bar.addWidget(box, *divmod(i, TOOLBAR_COLUMNS))
        reset = QPushButton("Reset view")
        reset.clicked.connect(self.reset_view)
        bar.addWidget(reset, *divmod(len(TOGGLES), TOOLBAR_COLUMNS))
        bar.setColumnStretch(TOOLBAR_COLUMNS, 1)
        return bar

    # ------------------------------------------------------------------ content
    def set_fitted(self, faces: np.ndarray, posed_verts: np.ndarray,
                   rest_verts: np.ndarray | None) -> None:
        """Show a fit: faces (F, 3), its meshes at its fitted frames posed_verts (T, V, 3) (the
        scene is laid out around all of them) and the rest-pose vertices (V, 3), in metres.
        Shows the first fitted frame's pose until :meth:`show_pose` gives the frame's."""
        if self.plotter is None:
            return
        self._fit = (np.asarray(posed_verts, dtype=np.float64), np.asarray(faces))
        self._rest = None if rest_verts is None else np.asarray(rest_verts, dtype=np.float64)
        self._posed_mesh = pv.PolyData.from_regular_faces(self._fit[0][0].copy(), self._fit[1])
        self.plotter.add_mesh(self._posed_mesh, color="slategray", smooth_shading=True,
                              name="posed", reset_camera=False, render=False)
        self._rebuild_scene()
        self.plotter.render()

    def set_elliptical(self, verts: np.ndarray | None, faces: np.ndarray | None = None) -> None:
        """Show the elliptical solid (core/measure/elliptical_solid.py), or remove it (None)."""
        if self.plotter is None:
            return
        self._solid = None if verts is None else (np.asarray(verts, dtype=np.float64),
                                                  np.asarray(faces))
        self._rebuild_scene()
        self.plotter.render()

    def show_pose(self, frame_idx: int, verts: np.ndarray, how: str) -> None:
        """Pose the fitted mesh as ``verts`` (V, 3) at clip frame ``frame_idx``, found as
        ``how`` says (core.fit.motion.ShownPose.label)."""
        if self.plotter is None or self._fit is None:
            return
        self.frame_label = how
        self._posed_mesh.points[:] = verts
        self._label_actor.set_text("upper_left", f"Frame {frame_idx}: {how}")
        self.plotter.render()

    def fitted_points(self) -> np.ndarray | None:
        """(V, 3) vertices of the fitted mesh as posed now, metres; None when none is shown."""
        return None if self._posed_mesh is None else np.asarray(self._posed_mesh.points)

    def clear(self) -> None:
        """Remove everything shown."""
        if self.plotter is None:
            return
        self._fit, self._rest, self._solid, self._posed_mesh = None, None, None, None
        self.frame_label = ""
        self.plotter.remove_actor([name for *_, names in TOGGLES.values() for name in names],
                                  render=False)
        self._label_actor.set_text("upper_left", "")
        self.plotter.render()

    def reset_view(self) -> None:
        """Look at everything shown from the default isometric direction."""
        if self.plotter is None:
            return
        self._reset_camera()
        self.plotter.render()

    def _reset_camera(self) -> None:
        self.plotter.view_isometric(render=False)
        # the bodies side by side stay in view across the width of the dock, however its
        # height changes (a tall dock, or one resized after the camera was placed)
        self.plotter.camera.SetUseHorizontalViewAngle(True)
        self.plotter.reset_camera(render=False)

    def close_viewer(self) -> None:
        """Release the VTK render window; the widget shows nothing afterwards."""
        if self.plotter is not None:
            self.plotter.close()
            self.plotter = None

    def closeEvent(self, event: QCloseEvent) -> None:  # noqa: N802 (Qt's name)
        self.close_viewer()
        super().closeEvent(event)

    # ------------------------------------------------------------------ scene
    def _rebuild_scene(self) -> None:
        """Place the comparison bodies, size the water, arrow and scale bar to them, and
        reset the camera (no render)."""
        self._place_comparison()
        actors = self.plotter.renderer.actors
        shown = [actors[name].mapper.dataset.points
                 for name in ("posed", "rest", "elliptical") if name in actors]
        if not shown:
            self.plotter.remove_actor(["water", "camera", "scale_bar", "scale_label"],
                                      render=False)
            return
        lo, hi = _bounds(np.concatenate(shown))
        animal = _bounds(self._fit[0]) if self._fit is not None else (lo, hi)
        body_length = float(np.ptp(shown[0], axis=0).max())
        self._add_decor((lo, hi), animal, body_length)
        self._apply_toggles()
        self._reset_camera()

    def _place_comparison(self) -> None:
        bodies = [] if self._rest is None else [self._rest]
        if self._solid is not None:
            bodies.append(self._solid[0])
        self.plotter.remove_actor(["rest", "elliptical"], render=False)
        if not bodies:
            return
        width = max(np.ptp(b[:, 1]) for b in bodies)
        if self._fit is None:
            centre = np.zeros(3)
        else:
            lo, hi = _bounds(self._fit[0])
            centre = (lo + hi) / 2.0
            centre[1] = hi[1] + width
        if self._rest is not None:
            rest = pv.PolyData.from_regular_faces(_centred_at(self._rest, centre), self._fit[1])
            self.plotter.add_mesh(rest, color="silver", smooth_shading=True, name="rest",
                                  reset_camera=False, render=False)
            centre = centre + [0.0, SPACING * width, 0.0]
        if self._solid is not None:
            solid = pv.PolyData.from_regular_faces(_centred_at(self._solid[0], centre),
                                                   self._solid[1])
            self.plotter.add_mesh(solid, color="orange", opacity=0.5, name="elliptical",
                                  reset_camera=False, render=False)

    def _add_decor(self, scene: tuple[np.ndarray, np.ndarray],
                   animal: tuple[np.ndarray, np.ndarray], length: float) -> None:
        """Water plane around all bodies, camera arrow above the animal's swept box, scale bar
        in front; ``scene`` and ``animal`` are (lower, upper) box corners, ``length`` a body's
        length (m), which sizes the margins and the arrow."""
        (lo, hi), (animal_lo, animal_hi) = scene, animal
        margin = WATER_MARGIN * length
        centre = (lo + hi) / 2.0
        water = pv.Plane(center=(centre[0], centre[1], 0.0), direction=(0.0, 0.0, 1.0),
                         i_size=hi[0] - lo[0] + 2 * margin, j_size=hi[1] - lo[1] + 2 * margin)
        self.plotter.add_mesh(water, color="royalblue", opacity=0.25, name="water",
                              reset_camera=False, render=False)
        above = (animal_lo + animal_hi) / 2.0
        above[2] = max(animal_hi[2], 0.0) + ARROW_HEIGHT * length
        arrow = pv.Arrow(start=above, direction=(0.0, 0.0, -1.0), scale=ARROW_LENGTH * length)
        self.plotter.add_mesh(arrow, color="black", name="camera", reset_camera=False,
                              render=False)
        start = np.array([lo[0], lo[1] - margin / 2.0, 0.0])
        end = start + [SCALE_BAR_M, 0.0, 0.0]
        self.plotter.add_mesh(pv.Line(start, end), color="black", line_width=4,
                              name="scale_bar", reset_camera=False, render=False)
        label_at = (start + end) / 2.0 - [0.0, margin / 3.0, 0.0]
        self.plotter.add_point_labels([label_at], [f"{SCALE_BAR_M:g} m"],
                                      font_size=12, shape_opacity=0.0, always_visible=True,
                                      show_points=False, name="scale_label",
                                      reset_camera=False, render=False)

    def _apply_toggles(self) -> None:
        actors = self.plotter.renderer.actors
        for key, (*_, names) in TOGGLES.items():
            for name in names:
                if name in actors:
                    actors[name].SetVisibility(self.toggles[key].isChecked())

    def _on_toggled(self) -> None:
        if self.plotter is not None:
            self._apply_toggles()
            self.plotter.render()
