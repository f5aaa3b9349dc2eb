"""A synthetic clip's files written frame by frame, whichever renderer drew it: the video at
the delivered size, the true masks and part masks, then the telemetry and truth.json.

A renderer draws each frame at the scene's size (``config.supersample`` times the delivered
one) with the share of each pixel the animal covers there; the video is downscaled by area
and the true mask is the delivered pixels at least half covered (``core.coverage.majority``).
"""

from pathlib import Path
from types import TracebackType

import cv2
import numpy as np
import torch

from dolphinfit.core.coverage import majority, white_squares
from dolphinfit.core.io.json_file import write_json
from dolphinfit.core.measure.condition import body_condition
from dolphinfit.core.measure.mesh import body_length, mesh_volume
from dolphinfit.core.synth.animal import SwimmingAnimal
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import (
    TRUTH_SCHEMA_VERSION, ClipFiles, clip_files, write_part_masks,
)
from dolphinfit.core.synth.motion import Motion
from dolphinfit.core.synth.parts import PART_NAMES
from dolphinfit.core.synth.telemetry import write_altitude, write_dji_srt
from dolphinfit.core.synth.video_out import open_clip_writer


class ClipRecorder:
    """Writes one clip's files into ``out_dir`` (a context manager: the video is closed on
    leaving it, also after an error)."""

    def __init__(self, config: SynthConfig, out_dir: Path, renderer: str) -> None:
        self.config, self.renderer = config, renderer
        self.files = clip_files(Path(out_dir), config)
        self.files.masks_dir.mkdir(parents=True, exist_ok=True)
        self.writer = open_clip_writer(self.files.video, config)
        self.size = (config.width_px, config.height_px)
        self.visible: list[bool] = []
        self.seeds: list[list[int] | None] = []
        self.parts: dict[str, list[np.ndarray]] = {name: [] for name in PART_NAMES}

    def __enter__(self) -> "ClipRecorder":
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> None:
        self.writer.close()

    def add(self, frame_bgr: np.ndarray, coverage: np.ndarray,
            part_coverages: list[np.ndarray], visible: bool) -> None:
        """The next frame: (H, W, 3) uint8 BGR at the scene's size, the share of each pixel
        the animal covers, the same for each part of ``PART_NAMES``, and whether the animal
        shows (else its masks are empty)."""
        self.writer.write(downscaled(frame_bgr, self.size))
        t = len(self.visible)
        mask = true_mask(coverage, self.size) & visible
        cv2.imwrite(str(self.files.masks_dir / f"{t:06d}.png"),
                    np.where(mask, 255, 0).astype(np.uint8))
        self.visible.append(visible)
        self.seeds.append(seed_px(mask))
        for name, share in zip(PART_NAMES, part_coverages, strict=True):
            self.parts[name].append(np.packbits(true_mask(share, self.size) & mask, axis=-1))

    def finish(self, animal: SwimmingAnimal, mate: Motion | None) -> ClipFiles:
        """The telemetry, the part masks and truth.json; the clip's files."""
        config, files, motion = self.config, self.files, animal.motion
        write_altitude(files.altitude_csv, motion.time_s, animal.altitude_m)
        write_dji_srt(files.srt, motion.time_s, animal.altitude_m, config.fps,
                      config.launch_height_m)
        write_part_masks(files.parts, self.parts,
                         (config.num_frames, config.height_px, config.width_px))
        _write_truth(files.truth_json, config, self.renderer, animal, self.visible, self.seeds,
                     mate)
        return files


def true_mask(share: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """(H, W) bool true mask at ``size`` (width, height) from the scene's coverage: the share
    of each delivered pixel covered (by area), then ``core.coverage.majority``."""
    share = downscaled(share, size)
    return majority(share, white_squares(*share.shape))


def downscaled(image: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """``image`` at ``size`` (width, height) by pixel area; itself when already that size."""
    if image.shape[1::-1] == size:
        return image
    return cv2.resize(image, size, interpolation=cv2.INTER_AREA)


def seed_px(mask: np.ndarray) -> list[int] | None:
    """[x, y] of the mask's deepest interior pixel (farthest from its edge); None if empty."""
    if not mask.any():
        return None
    distance = cv2.distanceTransform(mask.astype(np.uint8), cv2.DIST_L2, 5)
    row, col = np.unravel_index(int(np.argmax(distance)), distance.shape)
    return [int(col), int(row)]


def _write_truth(path: Path, config: SynthConfig, renderer: str, animal: SwimmingAnimal,
                 visible: list[bool], seeds: list[list[int] | None],
                 mate: Motion | None) -> None:
    """truth.json: the animal's size and condition, its shape and every frame's pose, a
    point inside its mask (``seed_px``), the renderer that drew it and, with a companion, the
    companion's position."""
    model, betas, motion, altitude = animal.model, animal.betas, animal.motion, animal.altitude_m
    with torch.no_grad():
        rest = model.forward_rest(betas)[0]
        volume = float(mesh_volume(rest, model.faces))
        length = float(body_length(rest, model.rostrum_idx, model.notch_idx))
    condition = body_condition(np.float64(length), np.float64(volume))
    truth = {
        "schema_version": TRUTH_SCHEMA_VERSION,
        "renderer": renderer,
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
