"""One synthetic clip drawn by VTK (``vtk_clips.scene``), written as ``core.synth`` writes its
own (``core.synth.recorder``): the same animal, motion and altitudes for the same
configuration, another renderer's pixels.

What the configuration asks of the water that VTK draws otherwise: its colour, attenuation
and seabed are the layers' (module doc of ``scene``); ``sea_state`` and ``glitter`` are a
low-frequency brightness of the surface and sparse sun glints laid over the whole frame;
refraction, ripples, white water and wet highlights are not drawn. Blur, sensor noise, the
delivered size and the codec are the configuration's, as for ``core.synth``.
"""

import threading
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import torch

from dolphinfit.core.bench.vtk_split import VTK_RENDERER
from dolphinfit.core.camera import NadirCamera
from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel
from dolphinfit.core.synth.animal import companion_animal, swimming_animal
from dolphinfit.core.synth.compose import VISIBLE_CONTRAST, finish
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import ClipFiles
from dolphinfit.core.synth.parts import part_faces
from dolphinfit.core.synth.recorder import ClipRecorder
from dolphinfit.vtk_clips.scene import FlatView, ShadedView

RENDER_STAGE = "render"
WINDOW_MARGIN_PX = 8         # the flat views' window: the animals' box grown by this
SURFACE_SCALE_PX = 40.0      # the surface's brightness varies over this many pixels
SURFACE_GAIN = 0.06          # … by this share at sea state 1
GLINTS_PER_MPX = 400.0       # sun glints per million pixels at glitter 1
GLINT_LEVEL = 0.9


def make_vtk_clip(config: SynthConfig, out_dir: Path,
                  progress: ProgressCallback | None = None,
                  cancel: threading.Event | None = None) -> ClipFiles:
    """Draw ``config`` with VTK into ``out_dir`` (module doc); deterministic for
    ``config.seed`` on one VTK and OpenGL. Progress and cancel as ``core.synth.clip``'s."""
    rng = np.random.default_rng(config.seed)
    animal = swimming_animal(config, rng)
    scene = replace(config, width_px=config.width_px * config.supersample,
                    height_px=config.height_px * config.supersample, supersample=1)
    intrinsics = CameraIntrinsics.from_sensor(scene.focal_mm, scene.sensor_width_mm,
                                              scene.width_px, scene.height_px)
    extra_rng = np.random.default_rng([config.seed, 3])
    mate_motion, mate_verts = companion_animal(config, animal.model, animal.motion, extra_rng)
    faces = animal.model.faces.numpy()
    with torch.no_grad():
        rest = animal.model.forward_rest(animal.betas)[0]
    normals_z = _vertex_normals_z(rest.numpy(), faces)
    flukes, rostrum = (part.numpy() for part in part_faces(animal.model, animal.betas))
    boxes = _boxes(intrinsics, animal.altitude_m, animal.verts, mate_verts)
    window = tuple(int(side) for side in (boxes[:, 2:] - boxes[:, :2]).max(0) + 1)
    shaded = ShadedView(scene, intrinsics, faces, normals_z, mate_verts is not None)
    flat = FlatView(faces, (flukes, rostrum), window, mate_verts is not None)
    noise_rng = np.random.default_rng([config.seed, 1])
    surface_rng = np.random.default_rng([config.seed, 5])
    size = (scene.height_px, scene.width_px)
    try:
        with ClipRecorder(config, out_dir, VTK_RENDERER) as recorder:
            for t in range(config.num_frames):
                check_cancel(cancel)
                verts = animal.verts[t].numpy()
                mate = None if mate_verts is None else mate_verts[t].numpy()
                altitude = float(animal.altitude_m[t])
                frame = shaded.render(verts, mate, altitude)
                water = shaded.render(verts, mate, altitude, show_animal=False)
                corner = (int(boxes[t, 0]), int(boxes[t, 1]))
                shares = np.zeros(size + (3,), np.float32)
                rows = slice(corner[1], corner[1] + window[1])
                cols = slice(corner[0], corner[0] + window[0])
                shares[rows, cols] = flat.shares(verts, mate, altitude, intrinsics,
                                                 corner)[:size[0] - corner[1],
                                                         :size[1] - corner[0]]
                frame = frame * _surface(size, config, surface_rng)[..., None]
                glints = _glints(size, config, surface_rng)
                covered = shares[..., 0]
                contrast = (float((np.abs(frame - water).sum(-1) * covered).sum()
                                  / (3.0 * covered.sum())) if covered.sum() >= 1.0 else 0.0)
                recorder.add(finish(frame, glints, config.blur_px, config.noise_sd, noise_rng),
                             covered, [shares[..., 1], shares[..., 2]],
                             contrast >= VISIBLE_CONTRAST)
                if progress is not None:
                    progress(Progress(RENDER_STAGE, t + 1, config.num_frames))
    finally:
        shaded.close()
        flat.close()
    return recorder.finish(animal, mate_motion)


def _boxes(intrinsics: CameraIntrinsics, altitude_m: np.ndarray, verts: torch.Tensor,
           mate_verts: torch.Tensor | None) -> np.ndarray:
    """(T, 4) x0, y0, x1, y1 of each frame's window for the flat views: the box of the
    animals' projected vertices grown by ``WINDOW_MARGIN_PX``, inside the frame."""
    camera = NadirCamera(intrinsics, torch.as_tensor(altitude_m), refraction=False)
    points = verts if mate_verts is None else torch.cat([verts, mate_verts], 1)
    xy = camera.project(points.double()).numpy()
    low = np.floor(xy.min(1)) - WINDOW_MARGIN_PX
    high = np.ceil(xy.max(1)) + WINDOW_MARGIN_PX
    frame = np.array([intrinsics.width_px - 1, intrinsics.height_px - 1])
    return np.column_stack([np.clip(low, 0, frame), np.clip(high, 0, frame)]).astype(int)


def _vertex_normals_z(verts: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(V,) the up component of each vertex's area-weighted normal."""
    corners = verts[faces]
    face_normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals = np.zeros_like(verts)
    for k in range(3):
        np.add.at(normals, faces[:, k], face_normals)
    return normals[:, 2] / np.maximum(np.linalg.norm(normals, axis=1), 1e-12)


def _surface(size: tuple[int, int], config: SynthConfig,
             rng: np.random.Generator) -> np.ndarray:
    """(H, W) brightness of the surface: 1 ± ``SURFACE_GAIN`` × sea state, smooth over
    ``SURFACE_SCALE_PX``."""
    field = cv2.GaussianBlur(rng.standard_normal(size).astype(np.float32), (0, 0),
                             SURFACE_SCALE_PX)
    field /= max(float(field.std()), 1e-6)
    return 1.0 + SURFACE_GAIN * config.sea_state * field


def _glints(size: tuple[int, int], config: SynthConfig,
            rng: np.random.Generator) -> np.ndarray:
    """(H, W) sun glints: ``GLINTS_PER_MPX`` × glitter points a million pixels, each a
    pixel bright."""
    glints = np.zeros(size, np.float32)
    count = rng.poisson(GLINTS_PER_MPX * config.glitter * size[0] * size[1] / 1e6)
    glints[rng.integers(0, size[0], count), rng.integers(0, size[1], count)] = GLINT_LEVEL
    return glints
