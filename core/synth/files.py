"""Where a synthetic clip's files go, and its part masks (no rendering here, so finding a
cached clip loads no model stack)."""

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.synth.config import SynthConfig

LOSSY_CODEC = ("mp4v", ".mp4")       # OpenCV's writable lossy codec (reference/platform.md §5)
LOSSLESS_CODEC = ("FFV1", ".mkv")
# 2: true masks by core.coverage.majority of the coverage downscaled by area (1 counted every
# half-covered pixel of the supersampled scene in, 0.03–0.21 px outside the outline)
TRUTH_SCHEMA_VERSION = 2
OWN_RENDERER = "dolphinfit"      # truth.json names the renderer that drew the clip


@dataclass(frozen=True)
class ClipFiles:
    """Where a synthetic clip's files are."""

    video: Path
    masks_dir: Path
    altitude_csv: Path
    srt: Path
    truth_json: Path
    parts: Path


def clip_files(out_dir: Path, config: SynthConfig) -> ClipFiles:
    """The file names of a clip made from ``config`` in ``out_dir``."""
    suffix = (LOSSY_CODEC if config.effects.compression else LOSSLESS_CODEC)[1]
    return ClipFiles(video=out_dir / f"clip{suffix}", masks_dir=out_dir / "masks",
                     altitude_csv=out_dir / "altitude.csv", srt=out_dir / "clip.SRT",
                     truth_json=out_dir / "truth.json", parts=out_dir / "parts.npz")


def made_from(files: ClipFiles, config: SynthConfig, renderer: str = OWN_RENDERER) -> bool:
    """Whether the clip in ``files`` is whole (truth, video and part masks) and was made from
    ``config`` by ``renderer`` under the current rules: its truth's schema is
    ``TRUTH_SCHEMA_VERSION``, it names the renderer (dolphinfit's own where it names none) and
    its recorded configuration reads back equal to it (fields added since it was made take
    their defaults, which render clips as before them)."""
    if not (files.truth_json.exists() and files.video.exists() and files.parts.exists()):
        return False
    try:
        truth = json.loads(files.truth_json.read_text(encoding="utf-8"))
        return (truth.get("schema_version") == TRUTH_SCHEMA_VERSION
                and truth.get("renderer", OWN_RENDERER) == renderer
                and SynthConfig.from_json(truth["config"]) == config)
    except (OSError, ValueError, KeyError, TypeError, InputError):
        return False


def write_part_masks(path: Path, masks: dict[str, list[np.ndarray]],
                     shape: tuple[int, int, int]) -> None:
    """``parts.npz``: per part name its (T, H, W) bool masks, bit-packed along the last axis,
    and their ``shape``. ``masks``: name → T frames of packed rows (H, ⌈W/8⌉) uint8."""
    np.savez_compressed(path, shape=np.asarray(shape, dtype=np.int64),
                        **{name: np.stack(frames) for name, frames in masks.items()})


def read_part_masks(path: Path) -> dict[str, np.ndarray]:
    """The part masks of ``parts.npz``: name → (T, H, W) bool."""
    with np.load(path, allow_pickle=False) as data:
        shape = tuple(int(n) for n in data["shape"])
        return {name: np.unpackbits(data[name], axis=-1, count=shape[-1]).astype(bool)
                for name in data.files if name != "shape"}
