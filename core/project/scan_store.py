"""A clip's scan kept with its project, and what the clip list says of each clip.

The scan of a project clip (core/scan/) is kept beside the project file, as
``PROJECT.scans/<clip key>_scan.json`` with its CSV (``_scan.csv``) for spreadsheets, so that
reopening the project does not scan again. Scan animal number n is the project's animal
"dolphin n": picking a frame of it in the app measures that animal.
"""

import threading
from collections.abc import Collection
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from dolphinfit.core.io.media import open_media
from dolphinfit.core.progress import ProgressCallback
from dolphinfit.core.project.fit_settings import clip_key
from dolphinfit.core.project.calibrations import calibrated_clip_telemetry
from dolphinfit.core.project.model import Animal, ClipEntry, Project
from dolphinfit.core.project.project_file import media_path
from dolphinfit.core.project.results import clip_telemetry
from dolphinfit.core.scan.clip_scan import ClipScan, scan_telemetry
from dolphinfit.core.scan.frame_scores import FrameScore, ScanSettings
from dolphinfit.core.scan.scan_files import write_scan_csv, write_scan_json

if TYPE_CHECKING:  # the scanner loads torch: the app reads and shows scans without it
    from dolphinfit.core.scan.scanner import Scanner

SCANS_SUFFIX = ".scans"  # beside PROJECT.dolphinfit: PROJECT.scans/<clip key>_scan.json


def scan_file(project_path: Path, clip_media: str | Path) -> Path:
    """Where a clip's scan is kept: ``PROJECT.scans/<clip key>_scan.json``."""
    folder = project_path.with_name(project_path.stem + SCANS_SUFFIX)
    return folder / f"{clip_key(clip_media)}_scan.json"


def save_scan(scan: ClipScan, path: Path) -> None:
    """Write the scan's JSON at ``path`` and its CSV beside it (atomically; the folder is made
    if needed)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    write_scan_json(path, scan)
    write_scan_csv(path.with_suffix(".csv"), scan)


def scan_clip(project_path: Path, project: Project, clip_idx: int, settings: ScanSettings,
              scanner: "Scanner", progress: ProgressCallback | None = None,
              cancel: threading.Event | None = None) -> ClipScan:
    """Scan a project clip with its camera and its altitudes through its calibration (frames
    without an altitude are put aside, not the clip); InputError when its media or altitude
    file cannot be read."""
    clip = project.clips[clip_idx]
    with open_media(media_path(project_path, clip)) as source:
        telemetry = clip_telemetry(project_path.parent, clip, source.clip)
        if telemetry is not None:
            telemetry = calibrated_clip_telemetry(project, clip_idx, telemetry)
        known = scan_telemetry(source.clip, telemetry,
                               clip.known_camera().intrinsics().focal_px)
        return scanner.scan(source, known, settings, progress, cancel)


def scan_animal_id(number: int) -> str:
    """The project animal that scan animal ``number`` is measured as."""
    return f"dolphin {number}"


def scan_animal(clip: ClipEntry, number: int) -> int | None:
    """Index of the project animal of scan animal ``number`` in ``clip``, or None."""
    wanted = scan_animal_id(number)
    return next((i for i, animal in enumerate(clip.animals) if animal.animal_id == wanted),
                None)


@dataclass(frozen=True)
class ClipStatus:
    """Where a clip stands in a day's work: its altitude, its scan (None: not scanned; else
    the animals found and those of them with a usable frame not put aside), frames measured,
    animals fitted."""

    has_altitude: bool
    animals_found: int | None
    animals_usable: int
    animals_measured: int
    frames_measured: int
    animals_fitted: int

    @property
    def none_found(self) -> bool:
        """Scanned, nothing found and nothing measured: the scan may have missed the animal
        (a 4-s clip gives the scan 4 samples), so a person looks before the clip counts as
        done."""
        return self.animals_found == 0 and self.frames_measured == 0

    @property
    def needs_work(self) -> bool:
        """No altitude, not scanned, none found and nothing measured, or an animal with a
        usable frame still unmeasured."""
        return (not self.has_altitude or self.animals_found is None or self.none_found
                or self.animals_measured < self.animals_usable)

    def text(self) -> str:
        """One line for the clip list."""
        parts = [] if self.has_altitude else ["no altitude"]
        if self.animals_found is None:
            parts.append("not scanned")
        elif self.none_found:
            parts.append("none found: check")
        else:
            parts.append(f"{self.animals_found} found")
        parts.append(f"{self.frames_measured} measured")
        if self.animals_fitted:
            parts.append(f"{self.animals_fitted} fitted")
        return " · ".join(parts)


def usable_frames(scan: ClipScan, rejected: Collection[tuple[int, int]],
                  number: int) -> list[FrameScore]:
    """Scan animal ``number``'s usable frames not put aside (``rejected``: the clip's
    (animal, frame) pairs), best first."""
    return [score for score in scan.best(number, len(scan.scores))
            if (number, score.frame_idx) not in rejected]


def _frames_measured(animal: Animal | None) -> int:
    """The animal's frames with a length: a frame opened for measuring is not measured yet."""
    return 0 if animal is None else sum(m.has_length for m in animal.measurements)


def clip_status(clip: ClipEntry, scan: ClipScan | None) -> ClipStatus:
    """The clip's ClipStatus, its scan read (None: not scanned)."""
    found = usable = measured = 0
    if scan is not None:
        for number in scan.animal_ids():
            found += 1
            if usable_frames(scan, clip.rejected_frames, number):
                usable += 1
                index = scan_animal(clip, number)
                measured += _frames_measured(None if index is None else clip.animals[index]) > 0
    return ClipStatus(
        has_altitude=clip.altitude is not None,
        animals_found=None if scan is None else found, animals_usable=usable,
        animals_measured=measured,
        frames_measured=sum(_frames_measured(animal) for animal in clip.animals),
        animals_fitted=sum(animal.fit_path is not None for animal in clip.animals))


def next_clip_needing_work(statuses: list[ClipStatus], after: int | None) -> int | None:
    """The first clip after ``after`` (wrapping round) that needs work, or None."""
    count = len(statuses)
    start = -1 if after is None else after
    for step in range(1, count + 1):
        index = (start + step) % count
        if statuses[index].needs_work:
            return index
    return None
