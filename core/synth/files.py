"""Where a synthetic clip's files go (no rendering here, so finding a cached clip loads no
model stack)."""

from dataclasses import dataclass
from pathlib import Path

from core.synth.config import SynthConfig

LOSSY_CODEC = ("mp4v", ".mp4")       # OpenCV's writable lossy codec (reference/platform.md §5)
LOSSLESS_CODEC = ("FFV1", ".mkv")


@dataclass(frozen=True)
class ClipFiles:
    """Where a synthetic clip's files are."""

    video: Path
    masks_dir: Path
    altitude_csv: Path
    srt: Path
    truth_json: Path


def clip_files(out_dir: Path, config: SynthConfig) -> ClipFiles:
    """The file names of a clip made from ``config`` in ``out_dir``."""
    suffix = (LOSSY_CODEC if config.effects.compression else LOSSLESS_CODEC)[1]
    return ClipFiles(video=out_dir / f"clip{suffix}", masks_dir=out_dir / "masks",
                     altitude_csv=out_dir / "altitude.csv", srt=out_dir / "clip.SRT",
                     truth_json=out_dir / "truth.json")
