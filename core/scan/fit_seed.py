"""The fit's automatic seed, taken from a scan of the fit's window.

The scan (``scanner``) searches the window's first sample as the one-frame automatic seed
(``auto_seed``) searches a frame, follows every animal it finds over the window at
``SEED_SAMPLE_FPS`` and keeps those that persist: a splash or glitter seen in one sample is
not taken, and an animal out of view in the first frames is found where it shows. The fit
takes the animal seen in the most samples; on a tie, the one nearest the middle of the frame
(median over its samples): a pilot keeps the animal being measured in the middle of the
frame, where the lens distorts least. Ranking a tie by the automatic seed's order took the
larger of a touching pair, not the one filmed, and on the held-out ``small_5k_turquoise`` a
seagrass strand that persisted as long as the dolphin. It is seeded by a click at the animal's centre in
its best usable frame (else its best-scored one). Where the scan keeps no animal the caller
falls back on the one-frame seed.
"""

import threading
from dataclasses import dataclass

import numpy as np

from dolphinfit.core.io.frame_source import FrameSource
from dolphinfit.core.io.video import frames_at_fps
from dolphinfit.core.progress import ProgressCallback
from dolphinfit.core.scan.clip_scan import ClipScan, ClipTelemetry
from dolphinfit.core.scan.frame_scores import FrameScore, ScanSettings
from dolphinfit.core.scan.scanner import Scanner
from dolphinfit.core.segment.segmenter import PointSeed

SEED_SAMPLE_FPS = 1.0   # the scan's samples per second of the fit's window


@dataclass(frozen=True)
class ScanPick:
    """The animal the fit takes: its scan number, the seed on its chosen frame, and one line
    for the user naming every animal the scan kept and which was taken."""

    animal_id: int
    seed: PointSeed
    line: str


def seed_at(score: FrameScore) -> PointSeed:
    """A click at the centre of a scanned animal in its frame."""
    return PointSeed(score.centre_x_px, score.centre_y_px, score.frame_idx)


def chosen_animal(scan: ClipScan) -> int | None:
    """The animal seen in the most samples, on a tie the one nearest the frame's middle
    (module doc); None where the scan kept none."""
    ids = scan.animal_ids()   # in the order the scan first saw them
    if not ids:
        return None
    return max(ids, key=lambda animal_id: (len(scan.of_animal(animal_id)),
                                           -off_centre(scan, animal_id),
                                           -ids.index(animal_id)))


def off_centre(scan: ClipScan, animal_id: int) -> float:
    """The animal's median distance from the frame's middle, in frame diagonals."""
    scores = scan.of_animal(animal_id)
    offsets = np.hypot([s.centre_x_px - scan.width_px / 2 for s in scores],
                       [s.centre_y_px - scan.height_px / 2 for s in scores])
    return float(np.median(offsets) / np.hypot(scan.width_px, scan.height_px))


def seed_frame(scan: ClipScan, animal_id: int) -> FrameScore:
    """The animal's best usable frame, else its best-scored one."""
    best = scan.best(animal_id, 1)
    return best[0] if best else max(scan.of_animal(animal_id), key=lambda s: s.quality)


def describe_pick(scan: ClipScan, animal_id: int, taken: FrameScore) -> str:
    """One line: the samples, each animal kept with how often it was seen, and the one taken."""
    samples = len(scan.sampled_frames)

    def seen(other: int) -> str:
        scores = scan.of_animal(other)
        length = np.median([s.length_m for s in scores])
        size = f"{length:.1f} m" if np.isfinite(length) else \
            f"{np.median([s.length_px for s in scores]):.0f} px"
        return f"dolphin {other} seen in {len(scores)} of {samples} samples, {size} long"

    others = [seen(other) for other in scan.animal_ids() if other != animal_id]
    count = len(scan.animal_ids())
    return (f"scan of {samples} frames: {count} animal{'s' if count != 1 else ''} kept; took "
            f"{seen(animal_id)}, from frame {taken.frame_idx} at ({taken.centre_x_px:.0f}, "
            f"{taken.centre_y_px:.0f})" + (f"; also {'; '.join(others)}" if others else ""))


def scan_pick(frames: FrameSource, telemetry: ClipTelemetry,
              window_s: tuple[float | None, float | None],
              scanner: Scanner | None = None, progress: ProgressCallback | None = None,
              cancel: threading.Event | None = None) -> ScanPick | None:
    """Scan the fit's window ``(start, end)`` seconds and pick its animal (module doc); None
    where the scan kept no animal."""
    samples = [int(t) for t in frames_at_fps(frames.clip, SEED_SAMPLE_FPS, *window_s)]
    scanner = scanner if scanner is not None else Scanner()
    scan = scanner.scan(frames, telemetry, ScanSettings(sample_fps=SEED_SAMPLE_FPS),
                        progress=progress, cancel=cancel, samples=samples)
    animal_id = chosen_animal(scan)
    if animal_id is None:
        return None
    taken = seed_frame(scan, animal_id)
    return ScanPick(animal_id, seed_at(taken), describe_pick(scan, animal_id, taken))
