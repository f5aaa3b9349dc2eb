"""Making one synthetic clip: video, true masks, altitude CSV, SRT and truth.json."""

import math
import threading
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import torch

from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.io.json_file import write_json
from dolphinfit.core.measure.condition import body_condition
from dolphinfit.core.measure.hw_ratios import load_hw_preset
from dolphinfit.core.measure.mesh import body_length, mesh_volume
from dolphinfit.core.model.model import DolphinModel
from dolphinfit.core.model.template import Template, load_template
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel
from dolphinfit.core.render.render import Appearance
from dolphinfit.core.render.shade import SGLight
from dolphinfit.core.model.sections import reshape_sections
from dolphinfit.core.synth.colouration import albedo
from dolphinfit.core.synth.compose import (
    VISIBLE_CONTRAST, DolphinLayer, Highlight, composite, finish, layer_mask, occlude,
    render_layer, ripple,
)
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import ClipFiles, clip_files, write_part_masks
from dolphinfit.core.synth.foreign import foreign_template
from dolphinfit.core.synth.motion import Motion, companion, swim
from dolphinfit.core.synth.parts import PART_NAMES, part_faces
from dolphinfit.core.synth.sea import Sea
from dolphinfit.core.synth.shape import draw_hw, random_betas, subdivide, warp_profiles
from dolphinfit.core.synth.telemetry import write_altitude, write_dji_srt
from dolphinfit.core.synth.video_out import open_clip_writer
from dolphinfit.core.synth.whitewater import Whitewater

TRUTH_SCHEMA_VERSION = 1
RENDER_STAGE = "render"


def make_clip(config: SynthConfig, out_dir: Path, progress: ProgressCallback | None = None,
              cancel: threading.Event | None = None) -> ClipFiles:
    """Render ``config`` into ``out_dir``; deterministic for ``config.seed``. The scene is
    rendered at ``config.supersample`` times the frame size; the video and the true masks are
    downscaled from it by area.

    Reports ``Progress(RENDER_STAGE, frames done, frames)``; once ``cancel`` is set it raises
    core.progress.Cancelled, leaving the folder without truth.json (an unfinished clip).
    """
    out_dir = Path(out_dir)
    rng = np.random.default_rng(config.seed)
    template, model, betas = synth_animal(config, rng)
    motion = swim(config, model.group_names, rng)
    altitude = (config.altitude_m + config.altitude_drift_m
                * np.sin(2 * math.pi * motion.time_s / (1.3 * config.duration_s)
                         + rng.uniform(0, 2 * math.pi)))
    with torch.no_grad():
        verts = model(betas, torch.as_tensor(motion.pose_aa),
                      torch.as_tensor(motion.transl)).verts.to(torch.float32)
    appearance = _appearance(template, config)
    scene = _rendered(config)
    intrinsics = CameraIntrinsics.from_sensor(scene.focal_mm, scene.sensor_width_mm,
                                              scene.width_px, scene.height_px)
    scattering = ((np.asarray(config.water_rgb), np.asarray(config.clarity_per_m))
                  if config.effects.scattering else None)
    sea = Sea(scene, rng)
    noise_rng = np.random.default_rng([config.seed, 1])
    extra_rng = np.random.default_rng([config.seed, 3])      # new effects keep the streams above
    mate_motion, mate_verts = _companion(config, model, motion, extra_rng)
    faces = model.faces
    parts = part_faces(model, betas)
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

    files = clip_files(out_dir, config)
    files.masks_dir.mkdir(parents=True, exist_ok=True)
    writer = open_clip_writer(files.video, config)
    delivered = (config.width_px, config.height_px)
    visible = []
    seeds: list[list[int] | None] = []
    packed: dict[str, list[np.ndarray]] = {name: [] for name in PART_NAMES}
    try:
        for t in range(config.num_frames):
            check_cancel(cancel)
            sea_frame = sea.frame(float(motion.time_s[t]), float(altitude[t]))
            mate = (None if mate_verts is None
                    else layer_at(t, mate_verts[t:t + 1], sea_frame.slope, False))
            layer = layer_at(t, verts[t:t + 1], sea_frame.slope, True)
            if layer is not None:
                layer = occlude(layer, mate)
            background = sea_frame.rgb if mate is None else composite(sea_frame.rgb, mate)[0]
            frame, contrast = composite(background, layer)
            if whitewater is not None:
                frame = whitewater.apply(frame, [layer, mate])
            is_visible = contrast >= VISIBLE_CONTRAST
            visible.append(is_visible)
            glints = sea_frame.glints if config.effects.glints else np.zeros_like(sea_frame.glints)
            if sea_frame.glitter is not None:
                glints = glints + sea_frame.glitter
            writer.write(_downscaled(finish(frame, glints, config.blur_px, config.noise_sd,
                                            noise_rng), delivered))
            fine_mask = layer_mask(layer if is_visible else None, scene.height_px,
                                   scene.width_px)
            mask = _downscaled_mask(fine_mask, delivered)
            cv2.imwrite(str(files.masks_dir / f"{t:06d}.png"), mask)
            seeds.append(_seed_px(mask))
            for k, name in enumerate(PART_NAMES):
                part = _downscaled_mask(_part_mask(layer, k, fine_mask), delivered) > 0
                packed[name].append(np.packbits(part & (mask > 0), axis=-1))
            if progress is not None:
                progress(Progress(RENDER_STAGE, t + 1, config.num_frames))
    finally:
        writer.close()

    write_altitude(files.altitude_csv, motion.time_s, altitude)
    write_dji_srt(files.srt, motion.time_s, altitude, config.fps, config.launch_height_m)
    write_part_masks(files.parts, packed,
                     (config.num_frames, config.height_px, config.width_px))
    _write_truth(files.truth_json, config, model, betas, motion, altitude, visible, seeds,
                 mate_motion)
    return files


def synth_animal(config: SynthConfig, rng: np.random.Generator
                 ) -> tuple[Template, DolphinModel, torch.Tensor]:
    """The clip's animal: its template (heights, sections, warp, finer mesh as configured),
    the model of it and its part scales; draws from ``rng`` first, as ``make_clip`` does."""
    template = foreign_template(_body(config), config.body)
    if config.effects.profile_warp:
        template = warp_profiles(template, rng, tie_heights=config.hw_table is not None)
    if config.effects.finer_mesh:
        template = subdivide(template)
    model = DolphinModel(template, dtype=torch.float64)
    betas = random_betas(model, config.length_m, config.shape_sd, rng,
                         tie_heights=config.hw_table is not None)
    return template, model, betas


def _body(config: SynthConfig) -> Template:
    """The template with the configured heights and sections (core/model/sections.py)."""
    template = load_template()
    if config.hw_table is None and config.section_exponent == 2.0:
        return template
    station_hw = None
    if config.hw_table is not None:
        station_hw = draw_hw(load_hw_preset(config.hw_table),
                             np.random.default_rng([config.seed, 4]))
    return reshape_sections(template, station_hw, config.section_exponent)


def _companion(config: SynthConfig, model: DolphinModel, target: Motion,
               rng: np.random.Generator) -> tuple[Motion | None, torch.Tensor | None]:
    """The second animal's motion and posed vertices (T, V, 3), or None when alone."""
    if config.companion_offset_m is None:
        return None, None
    betas = random_betas(model, config.companion_length_m, config.shape_sd, rng,
                         tie_heights=config.hw_table is not None)
    motion = companion(config, target, model.group_names, rng)
    with torch.no_grad():
        verts = model(betas, torch.as_tensor(motion.pose_aa),
                      torch.as_tensor(motion.transl)).verts.to(torch.float32)
    return motion, verts


def _seed_px(mask: np.ndarray) -> list[int] | None:
    """[x, y] of the mask's deepest interior pixel (farthest from its edge); None if empty."""
    if not mask.any():
        return None
    distance = cv2.distanceTransform(mask, cv2.DIST_L2, 5)
    row, col = np.unravel_index(int(np.argmax(distance)), distance.shape)
    return [int(col), int(row)]


def _part_mask(layer: DolphinLayer | None, part: int, mask: np.ndarray) -> np.ndarray:
    """(H, W) bool: where the part covers at least half a pixel of the true mask."""
    region = np.zeros(mask.shape, dtype=bool)
    if layer is not None and layer.parts is not None:
        h, w = layer.alpha.shape
        region[layer.y0:layer.y0 + h, layer.x0:layer.x0 + w] = layer.parts[..., part] >= 0.5
    return region & (mask > 0)


def _rendered(config: SynthConfig) -> SynthConfig:
    """The configuration of the scene as rendered: ``config`` at its supersampled size."""
    k = config.supersample
    return replace(config, width_px=config.width_px * k, height_px=config.height_px * k,
                   supersample=1)


def _downscaled(image: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """``image`` at ``size`` (width, height) by pixel area; itself when already that size."""
    if image.shape[1::-1] == size:
        return image
    return cv2.resize(image, size, interpolation=cv2.INTER_AREA)


def _downscaled_mask(mask: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """(H, W) uint8 mask at ``size``: 255 where the fine mask covers at least half a pixel."""
    coverage = _downscaled(np.where(mask > 0, 255, 0).astype(np.uint8), size)
    return np.where(coverage >= 128, 255, 0).astype(np.uint8)


def _appearance(template, config: SynthConfig) -> Appearance:
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


def _write_truth(path: Path, config: SynthConfig, model: DolphinModel, betas: torch.Tensor,
                 motion: Motion, altitude: np.ndarray, visible: list[bool],
                 seeds: list[list[int] | None], mate: Motion | None) -> None:
    """truth.json: the animal's size and condition, its shape and every frame's pose, a
    point inside its mask (``seed_px``) and, with a companion, the companion's position."""
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
             "depth_m": float(motion.depth_m[t]), "visible": bool(visible[t]),
             "seed_px": seeds[t],
             **({} if mate is None else {"companion_transl_m": mate.transl[t].tolist()})}
            for t in range(len(visible))],
    }
    write_json(path, truth)
