"""One clip's VTK scene: the shaded view a drone camera records and the flat views the truth is
counted from.

- **Shaded**: the animal (and a companion) as smooth-shaded meshes with vertex colours, dark
  back and pale belly by the rest pose's normals, lit by a sun and a weaker light from above
  with VTK's ambient, diffuse and Phong specular terms, 8× multisampled. Water: the clip's
  water colour behind everything, and translucent layers of it every ``LAYER_STEP_M`` down
  to ``LAYER_DEPTH_M`` (depth-peeled), each letting through exp(−2kΔz) of what lies below
  (k the mean of the clip's attenuations, down and back up); a seabed of the clip's colour
  where it has one.
- **Flat**: unlit, not multisampled, over black, at ``TRUTH_SAMPLES`` times the scene's
  resolution in a window around the animal: the target's faces white, its flukes and rostrum
  marked in the green and blue channels, a companion black (it hides the target where it lies
  above it). Averaging the samples gives each pixel's share of the animal and its parts.

The camera is the clip's nadir pinhole: VTK's view angle is the frame's vertical field of view,
and a window around the animal is the same camera with its view angle narrowed and its window
centre moved (``vtkCamera.SetWindowCenter``), so its pixels are the frame's, finer.
"""

import math

import numpy as np
import pyvista as pv

from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.synth.config import SynthConfig

MULTISAMPLES = 8
TRUTH_SAMPLES = 4            # flat views per pixel side
LAYER_STEP_M = 0.1
LAYER_DEPTH_M = 2.5
PEELS = 40
SUN_INTENSITY = 0.85
SKY_INTENSITY = 0.3
AMBIENT, DIFFUSE, SPECULAR, SPECULAR_POWER = 0.35, 0.7, 0.25, 20.0
# the back's and the belly's colour of each colouration (display values)
COLOURS = {"dark": ((0.16, 0.17, 0.19), (0.52, 0.53, 0.55)),
           "light_grey": ((0.45, 0.47, 0.50), (0.76, 0.77, 0.79))}
FAR_M = 1000.0               # the water layers' half size


class ShadedView:
    """The camera's view of the scene (module doc), ``width × height`` pixels."""

    def __init__(self, config: SynthConfig, intrinsics: CameraIntrinsics, faces: np.ndarray,
                 rest_normals_z: np.ndarray, companion: bool) -> None:
        self.plotter = pv.Plotter(off_screen=True, lighting="none",
                                  window_size=(intrinsics.width_px, intrinsics.height_px))
        self.plotter.enable_anti_aliasing("msaa", multi_samples=MULTISAMPLES)
        self.plotter.set_background(config.water_rgb)
        colours = _countershaded(config.colouration, rest_normals_z)
        self.actors = [self.plotter.add_mesh(
            _mesh(faces, colours), scalars="rgb", rgb=True, smooth_shading=True,
            ambient=AMBIENT, diffuse=DIFFUSE, specular=SPECULAR, specular_power=SPECULAR_POWER)
            for _animal in range(2 if companion else 1)]
        self._add_water(config)
        sun = config.sun_direction()
        self.plotter.add_light(pv.Light(position=tuple(100.0 * sun), focal_point=(0, 0, 0),
                                        light_type="scene light", intensity=SUN_INTENSITY))
        self.plotter.add_light(pv.Light(position=(0, 0, 100.0), focal_point=(0, 0, 0),
                                        light_type="scene light", intensity=SKY_INTENSITY))
        self.plotter.enable_depth_peeling(number_of_peels=PEELS)
        self.plotter.show(auto_close=False)    # the render window made once, off screen
        self.intrinsics = intrinsics

    def _add_water(self, config: SynthConfig) -> None:
        attenuation = 2.0 * float(np.mean(config.clarity_per_m))
        opacity = 1.0 - math.exp(-attenuation * LAYER_STEP_M)
        bottom = (LAYER_DEPTH_M if config.seabed_depth_m is None
                  else min(LAYER_DEPTH_M, config.seabed_depth_m))
        for depth in np.arange(0.0, bottom, LAYER_STEP_M):
            self.plotter.add_mesh(pv.Plane(center=(0, 0, -depth), direction=(0, 0, 1),
                                           i_size=2 * FAR_M, j_size=2 * FAR_M),
                                  color=config.water_rgb, opacity=opacity, lighting=False)
        if config.seabed_depth_m is not None:
            self.plotter.add_mesh(pv.Plane(center=(0, 0, -config.seabed_depth_m),
                                           direction=(0, 0, 1), i_size=2 * FAR_M,
                                           j_size=2 * FAR_M),
                                  color=config.seabed_rgb, ambient=0.6, diffuse=0.5)

    def render(self, verts: np.ndarray, mate_verts: np.ndarray | None, altitude_m: float,
               show_animal: bool = True) -> np.ndarray:
        """(H, W, 3) float32 RGB in [0, 1] of the scene with the animal (and companion) at
        these vertices, seen from ``altitude_m``; without the animal where not
        ``show_animal`` (the water it hides, for its contrast)."""
        _place(self.actors, verts, mate_verts)
        self.actors[0].visibility = show_animal
        _aim(self.plotter.camera, self.intrinsics, altitude_m)
        self.plotter.render()
        return self.plotter.screenshot(return_img=True).astype(np.float32) / 255.0

    def close(self) -> None:
        self.plotter.close()


class FlatView:
    """The flat views around the animal (module doc), ``window_px`` scene pixels a side."""

    def __init__(self, faces: np.ndarray, part_faces: tuple[np.ndarray, np.ndarray],
                 window_px: tuple[int, int], companion: bool) -> None:
        width, height = window_px
        self.window_px = window_px
        self.plotter = pv.Plotter(off_screen=True, lighting="none",
                                  window_size=(width * TRUTH_SAMPLES, height * TRUTH_SAMPLES))
        self.plotter.disable_anti_aliasing()
        self.plotter.set_background((0.0, 0.0, 0.0))
        flukes, rostrum = part_faces
        animal = _mesh(faces, None)
        animal.cell_data["parts"] = (np.column_stack([np.ones(len(faces)), flukes, rostrum])
                                     .astype(np.uint8) * 255)
        self.actors = [self.plotter.add_mesh(animal, scalars="parts", rgb=True, lighting=False,
                                             preference="cell")]
        if companion:
            self.actors.append(self.plotter.add_mesh(_mesh(faces, None), color=(0.0, 0.0, 0.0),
                                                     lighting=False))
        self.plotter.show(auto_close=False)

    def shares(self, verts: np.ndarray, mate_verts: np.ndarray | None, altitude_m: float,
               intrinsics: CameraIntrinsics, corner_px: tuple[int, int]) -> np.ndarray:
        """(h, w, 3) the share of each scene pixel of the window whose top-left pixel is
        ``corner_px`` (x, y) covered by the animal, its flukes and its rostrum."""
        _place(self.actors, verts, mate_verts)
        width, height = self.window_px
        _aim(self.plotter.camera, intrinsics, altitude_m, corner_px, self.window_px)
        self.plotter.render()
        samples = self.plotter.screenshot(return_img=True).astype(np.float32) / 255.0
        return samples.reshape(height, TRUTH_SAMPLES, width, TRUTH_SAMPLES, 3).mean((1, 3))

    def close(self) -> None:
        self.plotter.close()


def _aim(camera: pv.Camera, intrinsics: CameraIntrinsics, altitude_m: float,
         corner_px: tuple[int, int] | None = None,
         window_px: tuple[int, int] | None = None) -> None:
    """The camera at ``altitude_m`` looking straight down, world +y up the image: the whole
    frame, or the window of ``window_px`` (w, h) frame pixels from ``corner_px`` (module doc)."""
    camera.position = (0.0, 0.0, altitude_m)
    camera.focal_point = (0.0, 0.0, 0.0)
    camera.up = (0.0, 1.0, 0.0)
    camera.clipping_range = (0.05, altitude_m + 2 * LAYER_DEPTH_M + 10.0)
    if corner_px is None or window_px is None:
        height = intrinsics.height_px
        centre = (0.0, 0.0)
    else:
        width, height = window_px
        # the window's centre in frame pixels (centres at whole numbers), in the viewport
        # coordinates of a window centred on the optical axis ([-1, 1], y up)
        middle_x = corner_px[0] + (width - 1) / 2
        middle_y = corner_px[1] + (height - 1) / 2
        centre = ((middle_x - intrinsics.cx_px) / (width / 2),
                  -(middle_y - intrinsics.cy_px) / (height / 2))
    camera.view_angle = math.degrees(2 * math.atan(height / 2 / intrinsics.focal_px))
    camera.SetWindowCenter(*centre)


def _place(actors: list, verts: np.ndarray, mate_verts: np.ndarray | None) -> None:
    """The animal's (and its companion's) meshes moved to these vertices."""
    actors[0].mapper.dataset.points = verts
    if len(actors) > 1 and mate_verts is not None:
        actors[1].mapper.dataset.points = mate_verts


def _mesh(faces: np.ndarray, colours: np.ndarray | None) -> pv.PolyData:
    """A triangle mesh of ``faces`` (F, 3) with placeholder points, and vertex colours."""
    cells = np.column_stack([np.full(len(faces), 3), faces]).astype(np.int64).ravel()
    mesh = pv.PolyData(np.zeros((int(faces.max()) + 1, 3)), cells)
    if colours is not None:
        mesh.point_data["rgb"] = colours
    return mesh


def _countershaded(colouration: str, normals_z: np.ndarray) -> np.ndarray:
    """(V, 3) vertex colours: the back's colour where the rest pose's normal points up, the
    belly's where it points down, blended across the flanks."""
    back, belly = (np.asarray(c, dtype=np.float32) for c in COLOURS[colouration])
    belly_share = np.clip(0.5 - 0.75 * normals_z, 0.0, 1.0)[:, None]
    return (1.0 - belly_share) * back + belly_share * belly
