"""The project tree as immutable values: project → clips → animals → measured frames.

Every edit builds a new tree that shares the untouched branches with the old one, so an undo
step is just the previous tree and nothing is copied but the path to the change. Pixels live in
:class:`Measurement`; the camera and the altitude live on the clip (DESIGN.md §3, §8).

Width handles move along their station's perpendicular only, so a measurement stores each
edge as a signed distance from the midline along the station's unit normal (side A positive,
see core/measure/annotation.py). Moving the midline then carries the handles with it.
"""

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation import ALTITUDE_SOURCES, SIDES, Annotation, place_stations
from dolphinfit.core.measure.edge_sources import (
    EDGE_CLICKED, EDGE_SOURCE_DTYPE, EDGE_SOURCES, NO_EDGE,
)
from dolphinfit.core.measure.elliptical import TAIL_EXTRAPOLATED, TAIL_OPTIONS
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET
from dolphinfit.core.measure.lens import LensModel
from dolphinfit.core.measure.stations import NUM_STATIONS
from dolphinfit.core.project.fit_settings import FitSettings

MEDIA_KINDS = ("video", "image", "frames")
CAMERA_UNKNOWN = "camera unknown: Clip → Camera…"  # what a clip without a camera says


def _frozen_array(values: object, shape_tail: tuple[int, ...], dtype: type) -> np.ndarray:
    array = np.array(values, dtype=dtype).reshape((-1, *shape_tail) if shape_tail else (-1,))
    array.flags.writeable = False
    return array


@dataclass(frozen=True, eq=False)
class Measurement:
    """One measured frame of one animal, in image pixels.

    ``midline_px``: (N, 2) clicks rostrum tip → fluke notch (N may be 0 or 1 while drawing).
    ``offsets_px``: (S, 2) signed distance of the side A / side B edge from the midline along
    the station's normal, NaN where not placed. ``skipped``: (S,) stations marked not
    measurable (glare, splash). ``mirror_side``: None, "A" or "B" (that side doubled).
    ``edge_sources``: (S, 2) how each edge was placed (core.measure.edge_sources), NO_EDGE
    where none is; a placed edge given without a source counts as clicked.
    """

    frame_idx: int
    midline_px: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    offsets_px: np.ndarray = field(
        default_factory=lambda: np.full((NUM_STATIONS, 2), np.nan))
    skipped: np.ndarray = field(default_factory=lambda: np.zeros(NUM_STATIONS, bool))
    mirror_side: str | None = None
    notes: str = ""
    edge_sources: np.ndarray = field(
        default_factory=lambda: np.full((NUM_STATIONS, 2), NO_EDGE))

    def __post_init__(self) -> None:
        object.__setattr__(self, "midline_px", _frozen_array(self.midline_px, (2,), np.float64))
        object.__setattr__(self, "offsets_px", _frozen_array(self.offsets_px, (2,), np.float64))
        object.__setattr__(self, "skipped", _frozen_array(self.skipped, (), bool))
        sources = np.asarray(self.edge_sources, dtype=str)
        if (self.offsets_px.shape != (NUM_STATIONS, 2) or self.skipped.shape != (NUM_STATIONS,)
                or sources.shape != (NUM_STATIONS, 2)):
            raise ValueError(f"a measurement has {NUM_STATIONS} stations")
        if not np.isin(sources, (NO_EDGE, *EDGE_SOURCES)).all():
            raise ValueError(f"edge sources must be among {EDGE_SOURCES}")
        placed = np.isfinite(self.offsets_px)
        sources = np.where(placed, np.where(sources == NO_EDGE, EDGE_CLICKED, sources), NO_EDGE)
        object.__setattr__(self, "edge_sources", _frozen_array(sources, (2,), EDGE_SOURCE_DTYPE))
        if self.mirror_side not in (None, *SIDES):
            raise ValueError(f"mirror_side must be None, 'A' or 'B', got {self.mirror_side!r}")
        if self.frame_idx < 0:
            raise ValueError(f"frame_idx must be ≥ 0, got {self.frame_idx}")

    @property
    def has_length(self) -> bool:
        """Whether the midline has the two clicks a length needs."""
        return len(self.midline_px) >= 2

    def needed_sides(self) -> list[int]:
        """Side indices a width needs: both, or the mirrored one."""
        return [0, 1] if self.mirror_side is None else [SIDES.index(self.mirror_side)]

    def is_station_done(self) -> np.ndarray:
        """(S,) bool: stations skipped or with every needed side placed."""
        placed = np.isfinite(self.offsets_px[:, self.needed_sides()]).all(axis=1)
        return self.skipped | placed

    def used_edge_sources(self) -> np.ndarray:
        """(S, 2) ``edge_sources`` of the edges a width is measured from: NO_EDGE at skipped
        stations, at stations without every needed side, and on the side a mirror leaves out."""
        needed = self.needed_sides()
        has_width = ~self.skipped & np.isfinite(self.offsets_px[:, needed]).all(axis=1)
        return np.where(has_width[:, None] & np.isin([0, 1], needed), self.edge_sources, NO_EDGE)

    def to_annotation(self) -> Annotation | None:
        """The annotation of core.measure (edge points in pixels), None without a length."""
        if not self.has_length:
            return None
        stations = place_stations(self.midline_px)
        offsets = np.where(self.skipped[:, None], np.nan, self.offsets_px)
        edges = stations.points_px[:, None, :] + offsets[:, :, None] * stations.normals[:, None, :]
        return Annotation(frame_idx=self.frame_idx, midline_px=self.midline_px, edges_px=edges,
                          mirror_side=self.mirror_side)


@dataclass(frozen=True)
class Animal:
    """An animal seen in a clip: its ID, free notes and measured frames (in frame order), how
    to fit it, and its saved fit (a folder relative to the project file, or None) with what it
    was made from (core.project.fit_inputs; empty: not kept)."""

    animal_id: str
    notes: str = ""
    measurements: tuple[Measurement, ...] = ()
    fit_settings: FitSettings = FitSettings()
    fit_path: str | None = None
    fit_inputs: tuple[tuple[str, str], ...] = ()

    def measurement_at(self, frame_idx: int) -> int | None:
        """Index of the measurement of ``frame_idx``, or None."""
        return next((i for i, m in enumerate(self.measurements) if m.frame_idx == frame_idx),
                    None)


@dataclass(frozen=True)
class AltitudeSpec:
    """Where a clip's altitude comes from.

    ``path``: an SRT, altitude CSV or laser log, relative to the project file (None for a
    constant); ``constant_m``: the altitude of every frame when ``path`` is None.
    ``launch_height_m``: take-off point above the water, added to relative altitudes;
    ``time_offset_s``: laser-log alignment. ``source``: laser, barometer or manual, which sets
    the altitude error of the uncertainty.
    """

    path: str | None = None
    constant_m: float | None = None
    launch_height_m: float = 0.0
    time_offset_s: float = 0.0
    source: str = "manual"

    def __post_init__(self) -> None:
        if (self.path is None) == (self.constant_m is None):
            raise ValueError("an altitude comes from a file or a constant, exactly one")
        if self.constant_m is not None and not (np.isfinite(self.constant_m)
                                                and self.constant_m > 0):
            raise ValueError(f"altitude must be a positive number of metres, "
                             f"got {self.constant_m!r}")
        if not np.isfinite(self.launch_height_m) or not np.isfinite(self.time_offset_s):
            raise ValueError("launch height and time offset must be finite numbers")
        if self.source not in ALTITUDE_SOURCES:
            raise ValueError(f"altitude source must be one of {ALTITUDE_SOURCES}, "
                             f"got {self.source!r}")


@dataclass(frozen=True)
class ObjectShot:
    """One image of a calibration object: its length in pixels and the altitude recorded with
    it. ``image``: the image's name or path; ``ends_px``: the two ends clicked in the app,
    None for a length imported from a table."""

    image: str
    recorded_altitude_m: float
    pixel_length: float
    ends_px: tuple[tuple[float, float], tuple[float, float]] | None = None

    def __post_init__(self) -> None:
        for name in ("recorded_altitude_m", "pixel_length"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number, got {value!r}")


@dataclass(frozen=True)
class AltitudeCalibrationSet:
    """An object of known length photographed at several altitudes by one drone, camera and
    altimeter: what ``core.measure.altitude_calibration`` fits. ``name`` is how clips refer to
    it (e.g. "Mavic 3 barometer")."""

    name: str
    object_length_m: float
    camera: CameraPreset
    altimeter: str
    shots: tuple[ObjectShot, ...] = ()

    def __post_init__(self) -> None:
        if not self.name.strip():
            raise ValueError("a calibration needs a name")
        if not (np.isfinite(self.object_length_m) and self.object_length_m > 0):
            raise ValueError(f"object length must be a positive number of metres, "
                             f"got {self.object_length_m!r}")
        if self.altimeter not in ALTITUDE_SOURCES:
            raise ValueError(f"altimeter must be one of {ALTITUDE_SOURCES}, "
                             f"got {self.altimeter!r}")


@dataclass(frozen=True)
class ClipEntry:
    """A video, a still image or a folder of numbered frames, with its calibration.

    ``media_path``: relative to the project file's folder (POSIX separators). ``camera``: the
    camera and video mode, None while unknown (a still whose EXIF names none: nothing is
    measured until the user sets one); ``preset_name``: the preset it was chosen from (None:
    edited by hand, or the photo's own). ``altitude``: None until the user gives one.
    ``masks_path``: the clip's masks (a folder of %06d.png, an .npz or a mask video;
    core/io/masks.py), relative like the media. ``altitude_calibration``: the name of the
    project's calibration its altitudes are corrected by (None: as recorded). ``scan_path``:
    the clip's scan (core/scan/scan_files.py), relative like the media; ``rejected_frames``:
    (scan animal number, frame) pairs the user put aside in the frame picker. ``lens``: the
    camera's lens model (`dolphinfit calibrate lens`) measurements are taken through; None:
    measured as clicked. ``media_fingerprint``: the media's content when it was added
    (core/io/media_fingerprint.py; None: not taken).
    """

    media_path: str
    kind: str
    camera: CameraPreset | None
    preset_name: str | None = None
    altitude: AltitudeSpec | None = None
    animals: tuple[Animal, ...] = ()
    masks_path: str | None = None
    altitude_calibration: str | None = None
    scan_path: str | None = None
    rejected_frames: tuple[tuple[int, int], ...] = ()
    lens: LensModel | None = None
    media_fingerprint: str | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "rejected_frames", tuple(sorted(
            {(int(animal), int(frame)) for animal, frame in self.rejected_frames})))
        if self.kind not in MEDIA_KINDS:
            raise ValueError(f"media kind must be one of {MEDIA_KINDS}, got {self.kind!r}")

    @property
    def name(self) -> str:
        """The media's file or folder name."""
        return Path(self.media_path).name

    def known_camera(self) -> CameraPreset:
        """The clip's camera; InputError naming the clip while it is unknown."""
        if self.camera is None:
            raise InputError(f"{self.name}: {CAMERA_UNKNOWN}")
        return self.camera


@dataclass(frozen=True)
class Project:
    """A project: clips, and the elliptical settings shared by its results.

    ``hw_ratios``: an HW preset name or a CSV path; ``tail``: core.measure.elliptical's option.
    ``calibrations``: altitude calibrations the clips may name, each name once.
    """

    clips: tuple[ClipEntry, ...] = ()
    hw_ratios: str = DEFAULT_PRESET
    tail: str = TAIL_EXTRAPOLATED
    calibrations: tuple[AltitudeCalibrationSet, ...] = ()

    def __post_init__(self) -> None:
        if self.tail not in TAIL_OPTIONS:
            raise ValueError(f"tail must be one of {TAIL_OPTIONS}, got {self.tail!r}")
        names = [c.name for c in self.calibrations]
        if len(set(names)) != len(names):
            raise ValueError(f"two altitude calibrations share a name: {names}")
        unknown = {c.altitude_calibration for c in self.clips} - {None, *names}
        if unknown:
            raise ValueError(f"a clip names an altitude calibration the project lacks: "
                             f"{sorted(unknown)}")

    def calibration(self, name: str) -> AltitudeCalibrationSet:
        """The calibration called ``name`` (KeyError if none)."""
        for calibration in self.calibrations:
            if calibration.name == name:
                return calibration
        raise KeyError(name)


@dataclass(frozen=True)
class MeasurementKey:
    """Where a measurement sits in the tree: clip, animal and measurement indices."""

    clip: int
    animal: int
    measurement: int


def get_measurement(project: Project, key: MeasurementKey) -> Measurement:
    """The measurement at ``key`` (IndexError if there is none)."""
    return project.clips[key.clip].animals[key.animal].measurements[key.measurement]


def _replaced(items: tuple, idx: int, item: object) -> tuple:
    return (*items[:idx], item, *items[idx + 1:])


def with_clip(project: Project, clip_idx: int, clip: ClipEntry) -> Project:
    """``project`` with clip ``clip_idx`` replaced."""
    return replace(project, clips=_replaced(project.clips, clip_idx, clip))


def with_animal(project: Project, clip_idx: int, animal_idx: int, animal: Animal) -> Project:
    """``project`` with one animal replaced."""
    clip = project.clips[clip_idx]
    return with_clip(project, clip_idx,
                     replace(clip, animals=_replaced(clip.animals, animal_idx, animal)))


def with_measurement(project: Project, key: MeasurementKey, measurement: Measurement) -> Project:
    """``project`` with the measurement at ``key`` replaced."""
    animal = project.clips[key.clip].animals[key.animal]
    return with_animal(project, key.clip, key.animal, replace(
        animal, measurements=_replaced(animal.measurements, key.measurement, measurement)))


def add_clip(project: Project, clip: ClipEntry) -> Project:
    """``project`` with ``clip`` appended."""
    return replace(project, clips=(*project.clips, clip))


def add_animal(project: Project, clip_idx: int, animal: Animal) -> Project:
    """``project`` with ``animal`` appended to a clip."""
    clip = project.clips[clip_idx]
    return with_clip(project, clip_idx, replace(clip, animals=(*clip.animals, animal)))


def remove_animal(project: Project, clip_idx: int, animal_idx: int) -> Project:
    """``project`` without one animal (and its measurements)."""
    clip = project.clips[clip_idx]
    animals = clip.animals[:animal_idx] + clip.animals[animal_idx + 1:]
    return with_clip(project, clip_idx, replace(clip, animals=animals))


def add_measurement(project: Project, clip_idx: int, animal_idx: int,
                    measurement: Measurement) -> tuple[Project, MeasurementKey]:
    """``project`` with ``measurement`` inserted in frame order, and its key."""
    animal = project.clips[clip_idx].animals[animal_idx]
    if animal.measurement_at(measurement.frame_idx) is not None:
        raise ValueError(f"{animal.animal_id} is already measured on frame "
                         f"{measurement.frame_idx}")
    position = sum(m.frame_idx < measurement.frame_idx for m in animal.measurements)
    measurements = (*animal.measurements[:position], measurement,
                    *animal.measurements[position:])
    project = with_animal(project, clip_idx, animal_idx,
                          replace(animal, measurements=measurements))
    return project, MeasurementKey(clip_idx, animal_idx, position)


def remove_measurement(project: Project, key: MeasurementKey) -> Project:
    """``project`` without the measurement at ``key``."""
    animal = project.clips[key.clip].animals[key.animal]
    measurements = animal.measurements[:key.measurement] + animal.measurements[key.measurement + 1:]
    return with_animal(project, key.clip, key.animal, replace(animal, measurements=measurements))


def next_animal_id(clip: ClipEntry) -> str:
    """The first free ID of the form "dolphin N"."""
    taken = {a.animal_id for a in clip.animals}
    return next(f"dolphin {n}" for n in range(1, len(taken) + 2) if f"dolphin {n}" not in taken)


def with_calibration(project: Project, calibration: AltitudeCalibrationSet,
                     clip_indices: tuple[int, ...], replacing: str | None = None) -> Project:
    """``project`` with ``calibration`` in place of the one called ``replacing`` (appended
    when None), correcting exactly the clips ``clip_indices`` among those that named it."""
    kept = tuple(c for c in project.calibrations if c.name not in (replacing, calibration.name))
    old_names = {replacing, calibration.name} - {None}
    clips = tuple(replace(clip, altitude_calibration=calibration.name) if i in clip_indices
                  else replace(clip, altitude_calibration=None)
                  if clip.altitude_calibration in old_names else clip
                  for i, clip in enumerate(project.clips))
    return replace(project, calibrations=(*kept, calibration), clips=clips)

