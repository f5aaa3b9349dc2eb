"""Making one synthetic clip: video, true masks, altitude CSV, SRT and truth.json."""

import math
import threading
from pathlib import Path

import cv2
import numpy as np
import torch

from core.errors import InputError
from core.intrinsics import CameraIntrinsics
from core.io.json_file import write_json
from core.measure.condition import body_condition
from core.measure.mesh import body_length, mesh_volume
from core.model.model import DolphinModel
from core.model.template import load_template
from core.progress import Progress, ProgressCallback, check_cancel
from core.render.render import Appearance
from core.render.shade import SGLight
from core.synth.compose import (
    VISIBLE_CONTRAST, composite, finish, layer_mask, render_layer, ripple,
)
from core.synth.config import SynthConfig
from core.synth.files import LOSSLESS_CODEC, LOSSY_CODEC, ClipFiles, clip_files
from core.synth.motion import swim
from core.synth.sea import Sea
from core.synth.shape import random_betas, subdivide, warp_profiles
from core.synth.telemetry import write_altitude, write_dji_srt

TRUTH_SCHEMA_VERSION = 1
RENDER_STAGE = "render"


def make_clip(config: SynthConfig, out_dir: Path, progress: ProgressCallback | None = None,
              cancel: threading.Event | None = None) -> ClipFiles:
    """Render ``config`` into ``out_dir``; deterministic for ``config.seed``.

    Reports ``Progress(RENDER_STAGE, frames done, frames)``; once ``cancel`` is set it raises
    core.progress.Cancelled, leaving the folder without truth.json (an unfinished clip).
    """
    out_dir = Path(out_dir)
    rng = np.random.default_rng(config.seed)
    template = load_template()
    if config.effects.profile_warp:
        template = warp_profiles(template, rng)
    if config.effects.finer_mesh:
        template = subdivide(template)
    model = DolphinModel(template, dtype=torch.float64)
    betas = random_betas(model, config.length_m, config.shape_sd, rng)
    motion = swim(config, model.group_names, rng)
    altitude = (config.altitude_m + config.altitude_drift_m
                * np.sin(2 * math.pi * motion.time_s / (1.3 * config.duration_s)
                         + rng.uniform(0, 2 * math.pi)))
    with torch.no_grad():
        verts = model(betas, torch.as_tensor(motion.pose_aa),
                      torch.as_tensor(motion.transl)).verts.to(torch.float32)
    appearance = _appearance(template, config)
    intrinsics = CameraIntrinsics.from_sensor(config.focal_mm, config.sensor_width_mm,
                                              config.width_px, config.height_px)
    scattering = ((np.asarray(config.water_rgb), np.asarray(config.clarity_per_m))
                  if config.effects.scattering else None)
    sea = Sea(config, rng)
    noise_rng = np.random.default_rng([config.seed, 1])

    files = clip_files(out_dir, config)
    files.masks_dir.mkdir(parents=True, exist_ok=True)
    writer = _open_writer(files.video, config)
    visible = []
    faces = model.faces
    try:
        for t in range(config.num_frames):
            check_cancel(cancel)
            sea_frame = sea.frame(float(motion.time_s[t]), float(altitude[t]))
            layer = render_layer(verts[t:t + 1], faces, appearance, intrinsics,
                                 float(altitude[t]), config.effects.refraction, scattering)
            if layer is not None and config.effects.ripples:
                layer = ripple(layer, sea_frame.slope, float(altitude[t]) / intrinsics.focal_px)
            frame, contrast = composite(sea_frame.rgb, layer)
            is_visible = contrast >= VISIBLE_CONTRAST
            visible.append(is_visible)
            glints = sea_frame.glints if config.effects.glints else np.zeros_like(sea_frame.glints)
            writer.write(finish(frame, glints, config.blur_px, config.noise_sd, noise_rng))
            mask = layer_mask(layer if is_visible else None, config.height_px, config.width_px)
            cv2.imwrite(str(files.masks_dir / f"{t:06d}.png"), mask)
            if progress is not None:
                progress(Progress(RENDER_STAGE, t + 1, config.num_frames))
    finally:
        writer.release()

    write_altitude(files.altitude_csv, motion.time_s, altitude)
    write_dji_srt(files.srt, motion.time_s, altitude, config.fps, config.launch_height_m)
    _write_truth(files.truth_json, config, model, betas, motion, altitude, visible)
    return files


def _open_writer(path: Path, config: SynthConfig) -> cv2.VideoWriter:
    codec = (LOSSY_CODEC if config.effects.compression else LOSSLESS_CODEC)[0]
    path.parent.mkdir(parents=True, exist_ok=True)
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*codec), config.fps,
                             (config.width_px, config.height_px))
    if not writer.isOpened():
        raise InputError(f"{path}: OpenCV cannot write {codec} video here")
    return writer


def _appearance(template, config: SynthConfig) -> Appearance:
    """The template's albedo under a sun at the configured elevation and azimuth."""
    light = SGLight.overhead_sun(torch.float32)
    axes = light.axes.clone()
    axes[0] = torch.as_tensor(config.sun_direction(), dtype=axes.dtype)
    f_water = (torch.zeros(3) if config.effects.scattering
               else torch.tensor(config.clarity_per_m, dtype=torch.float32))
    return Appearance(albedo=torch.tensor(template.albedo / 255.0, dtype=torch.float32),
                      face_uvs=torch.tensor(template.uvs[template.face_uvs_idx],
                                            dtype=torch.float32),
                      light=SGLight(axes, light.sharpness, light.amplitude), f_water=f_water)


def _write_truth(path: Path, config: SynthConfig, model: DolphinModel, betas: torch.Tensor,
                 motion, altitude: np.ndarray, visible: list[bool]) -> None:
    """truth.json: the animal's size and condition, its shape and every frame's pose."""
    with torch.no_grad():
        rest = model.forward_rest(betas)[0]
        volume = float(mesh_volume(rest, model.faces))
        length = float(body_length(rest, model.rostrum_idx, model.notch_idx))
    condition = body_condition(np.float64(length), np.float64(volume))
    truth = {
        "schema_version": TRUTH_SCHEMA_VERSION,
        "volume_m3": volume,
        "length_m": length,
        "mass_kg": float(condition.mass_kg),
        "bci": float(condition.bci),
        "betas": betas.tolist(),
        "group_names": list(model.group_names),
        "config": config.to_json(),
        "frames": [
            {"frame": t, "time_s": float(motion.time_s[t]), "altitude_m": float(altitude[t]),
             "transl_m": motion.transl[t].tolist(), "pose_aa": motion.pose_aa[t].tolist(),
             "depth_m": float(motion.depth_m[t]), "visible": bool(visible[t])}
            for t in range(len(visible))],
    }
    write_json(path, truth)
