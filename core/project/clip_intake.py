"""Adding a day's clips to a project in one step: each video opened and checked, its DJI SRT
found beside it and read, its camera preset chosen from the video's size and the drone family
the SRT names, and every clip that cannot be used put aside with the reason.

A clip is put aside when it cannot be read, is shorter than ``MIN_DURATION_S``, has no SRT
beside it, or its SRT holds no altitude. A preset is sure when exactly one preset has the
video's size, or one of several also names a drone of the SRT's family; otherwise the first
is taken (or the default preset's lens at the video's size when none has it) and the clip's
note asks the user to check it.
"""

import threading
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from dolphinfit.core.camera_presets import CameraPreset, load_presets
from dolphinfit.core.errors import InputError
from dolphinfit.core.io.media import open_media
from dolphinfit.core.io.media_fingerprint import media_fingerprint
from dolphinfit.core.io.srt import SrtFamily, parse_srt, srt_altitude
from dolphinfit.core.io.telemetry import find_srt_sidecar
from dolphinfit.core.measure.annotation import ALTITUDE_SOURCE_OF_KIND
from dolphinfit.core.progress import Progress, ProgressCallback, check_cancel
from dolphinfit.core.project.model import AltitudeSpec, ClipEntry
from dolphinfit.core.project.new_project import default_camera
from dolphinfit.core.project.project_file import relative_media_path

MIN_DURATION_S = 1.0


@dataclass(frozen=True)
class CameraGuess:
    """The preset a clip gets, its name (None: the default lens at the clip's size), whether
    the guess is sure, and why, in words."""

    camera: CameraPreset
    preset_name: str | None
    sure: bool
    why: str


@dataclass(frozen=True)
class IntakeClip:
    """A clip ready to add, with its camera guess, and whether its SRT records height above
    the take-off point (the launch height is to be added, ``with_launch_height``)."""

    entry: ClipEntry
    camera: CameraGuess
    relative_altitude: bool


@dataclass(frozen=True)
class Intake:
    """The clips that can be added, and those put aside as "NAME: reason"."""

    clips: tuple[IntakeClip, ...]
    refused: tuple[str, ...]


def guess_camera(width_px: int, height_px: int, family: SrtFamily | None,
                 presets: Mapping[str, CameraPreset]) -> CameraGuess:
    """The module doc's choice of preset for a video of that size and SRT family."""
    size = f"{width_px}×{height_px}"
    matches = [name for name, p in presets.items()
               if (p.image_width_px, p.image_height_px) == (width_px, height_px)]
    if family is not None and len(matches) > 1:
        models = [m.strip() for m in family.models.split(",")]
        named = [n for n in matches if any(m in presets[n].description for m in models)]
        if len(named) == 1:
            return CameraGuess(presets[named[0]], named[0], True,
                               f"{named[0]}: {size} and an SRT of the {family.models} family")
    if len(matches) == 1:
        return CameraGuess(presets[matches[0]], matches[0], True,
                           f"{matches[0]}: the only preset at {size}")
    if matches:
        return CameraGuess(presets[matches[0]], matches[0], False,
                           f"{matches[0]} taken of {len(matches)} presets at {size} "
                           f"({', '.join(matches)}): check Clip → Camera…")
    camera, name = default_camera(width_px, height_px)
    return CameraGuess(camera, name, False,
                       f"no preset at {size}: {camera.description}; check Clip → Camera…")


def intake_clip(video: Path, project_dir: Path,
                presets: Mapping[str, CameraPreset]) -> IntakeClip:
    """A clip entry for ``video`` with its SRT's altitude and a camera guess; InputError
    with the reason when the clip cannot be used (module doc)."""
    with open_media(video) as source:
        clip, kind = source.clip, source.kind
    duration_s = clip.num_frames / clip.fps
    if kind != "video" or duration_s < MIN_DURATION_S:
        raise InputError(f"too short ({clip.num_frames} frames, {duration_s:.1f} s; at least "
                         f"{MIN_DURATION_S:g} s)")
    srt_path = find_srt_sidecar(video)
    if srt_path is None:
        raise InputError(f"no altitude: no {video.stem}.SRT beside it")
    srt = parse_srt(srt_path)
    samples = srt_altitude(srt)
    valid = samples.altitude_m[np.isfinite(samples.altitude_m)]
    if valid.size == 0:
        raise InputError(f"no altitude in {srt_path.name}")
    guess = guess_camera(clip.width_px, clip.height_px, srt.family, presets)
    spec = AltitudeSpec(path=relative_media_path(project_dir, srt_path),
                        source=ALTITUDE_SOURCE_OF_KIND["srt"])
    entry = ClipEntry(media_path=relative_media_path(project_dir, video), kind=kind,
                      camera=guess.camera, preset_name=guess.preset_name, altitude=spec,
                      media_fingerprint=media_fingerprint(video))
    return IntakeClip(entry, guess, srt.family.is_relative)


def intake(videos: Sequence[Path], project_dir: Path, known: set[str] = frozenset(),
           progress: ProgressCallback | None = None,
           cancel: threading.Event | None = None) -> Intake:
    """Each video checked (module doc), with progress per clip; videos whose media path is in
    ``known`` (already in the project) are skipped. Cancelled when ``cancel`` is set."""
    presets = load_presets()
    clips, refused = [], []
    for step, video in enumerate(videos):
        check_cancel(cancel)
        if relative_media_path(project_dir, video) not in known:
            try:
                clips.append(intake_clip(video, project_dir, presets))
            except (InputError, OSError, ValueError) as exc:
                refused.append(f"{video.name}: {exc}")
        if progress is not None:
            progress(Progress("add clips", step + 1, len(videos), video.name))
    return Intake(tuple(clips), tuple(refused))


def with_launch_height(clip: IntakeClip, launch_height_m: float) -> ClipEntry:
    """The clip's entry with ``launch_height_m`` added to a relative altitude."""
    if not clip.relative_altitude:
        return clip.entry
    return replace(clip.entry, altitude=replace(clip.entry.altitude,
                                                launch_height_m=launch_height_m))
