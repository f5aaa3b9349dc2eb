"""Making one synthetic clip with dolphinfit's own renderer: video, true masks, altitude CSV,
SRT and truth.json (``core.synth.recorder`` writes them)."""

import threading
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch

from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel
from dolphinfit.core.render.render import Appearance
from dolphinfit.core.render.shade import SGLight
from dolphinfit.core.synth.animal import companion_animal, swimming_animal
from dolphinfit.core.synth.colouration import albedo
from dolphinfit.core.synth.compose import (
    VISIBLE_CONTRAST, DolphinLayer, Highlight, composite, finish, layer_coverage, occlude,
    render_layer, ripple,
)
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import OWN_RENDERER, ClipFiles
from dolphinfit.core.synth.parts import PART_NAMES, part_faces
from dolphinfit.core.synth.recorder import ClipRecorder
from dolphinfit.core.synth.sea import Sea
from dolphinfit.core.synth.whitewater import Whitewater

RENDER_STAGE = "render"


def make_clip(config: SynthConfig, out_dir: Path, progress: ProgressCallback | None = None,
              cancel: threading.Event | None = None) -> ClipFiles:
    """Render ``config`` into ``out_dir``; deterministic for ``config.seed``. The scene is
    rendered at ``config.supersample`` times the frame size; the video and the true masks are
    downscaled from it by area (``core.synth.recorder``).

    Reports ``Progress(RENDER_STAGE, frames done, frames)``; once ``cancel`` is set it raises
    core.progress.Cancelled, leaving the folder without truth.json (an unfinished clip).
    """
    rng = np.random.default_rng(config.seed)
    animal = swimming_animal(config, rng)
    model, motion, altitude = animal.model, animal.motion, animal.altitude_m
    appearance = scene_appearance(animal.template, config)
    scene = _rendered(config)
    intrinsics = scene_intrinsics(config)
    scattering = ((np.asarray(config.water_rgb), np.asarray(config.clarity_per_m))
                  if config.effects.scattering else None)
    sea = Sea(scene, rng)
    noise_rng = np.random.default_rng([config.seed, 1])
    extra_rng = np.random.default_rng([config.seed, 3])      # new effects keep the streams above
    mate_motion, mate_verts = companion_animal(config, model, motion, extra_rng)
    faces = model.faces
    parts = part_faces(model, animal.betas)
    highlight = (Highlight(config.sun_direction(), config.wet_specular)
                 if config.wet_specular > 0 else None)
    gsd = float(config.altitude_m) / intrinsics.focal_px
    whitewater = Whitewater(scene, extra_rng, gsd) if config.splash > 0 else None

    def layer_at(t: int, verts_t: torch.Tensor, slope: np.ndarray,
                 with_parts: bool) -> DolphinLayer | None:
        layer = render_layer(verts_t, faces, appearance, intrinsics, float(altitude[t]),
                             config.effects.refraction, scattering,
                             parts if with_parts else (), highlight)
        if layer is not None and config.effects.ripples:
            layer = ripple(layer, slope, float(altitude[t]) / intrinsics.focal_px)
        return layer

    with ClipRecorder(config, out_dir, OWN_RENDERER) as recorder:
        for t in range(config.num_frames):
            check_cancel(cancel)
            sea_frame = sea.frame(float(motion.time_s[t]), float(altitude[t]))
            mate = (None if mate_verts is None
                    else layer_at(t, mate_verts[t:t + 1], sea_frame.slope, False))
            layer = layer_at(t, animal.verts[t:t + 1], sea_frame.slope, True)
            if layer is not None:
                layer = occlude(layer, mate)
            background = sea_frame.rgb if mate is None else composite(sea_frame.rgb, mate)[0]
            frame, contrast = composite(background, layer, config.body_contrast)
            if whitewater is not None:
                frame = whitewater.apply(frame, [layer, mate])
            glints = sea_frame.glints if config.effects.glints else np.zeros_like(sea_frame.glints)
            if sea_frame.glitter is not None:
                glints = glints + sea_frame.glitter
            size = (scene.height_px, scene.width_px)
            recorder.add(finish(frame, glints, config.blur_px, config.noise_sd, noise_rng),
                         layer_coverage(layer, *size),
                         [layer_coverage(layer, *size, k) for k in range(len(PART_NAMES))],
                         contrast >= VISIBLE_CONTRAST)
            if progress is not None:
                progress(Progress(RENDER_STAGE, t + 1, config.num_frames))
    return recorder.finish(animal, mate_motion)


def _rendered(config: SynthConfig) -> SynthConfig:
    """The configuration of the scene as rendered: ``config`` at its supersampled size."""
    k = config.supersample
    return replace(config, width_px=config.width_px * k, height_px=config.height_px * k,
                   supersample=1)


def scene_intrinsics(config: SynthConfig) -> CameraIntrinsics:
    """The camera the scene is rendered with: ``config``'s at its supersampled size."""
    scene = _rendered(config)
    return CameraIntrinsics.from_sensor(scene.focal_mm, scene.sensor_width_mm, scene.width_px,
                                        scene.height_px)


def scene_appearance(template, config: SynthConfig) -> Appearance:
    """The configured colouration under a sun at the configured elevation and azimuth."""
    light = SGLight.overhead_sun(torch.float32)
    axes = light.axes.clone()
    axes[0] = torch.as_tensor(config.sun_direction(), dtype=axes.dtype)
    f_water = (torch.zeros(3) if config.effects.scattering
               else torch.tensor(config.clarity_per_m, dtype=torch.float32))
    return Appearance(albedo=torch.tensor(albedo(template, config.colouration),
                                          dtype=torch.float32),
                      face_uvs=torch.tensor(template.uvs[template.face_uvs_idx],
                                            dtype=torch.float32),
                      light=SGLight(axes, light.sharpness, light.amplitude), f_water=f_water)


