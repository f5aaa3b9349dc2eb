"""Results of a project's measured frames: one elliptical estimate per frame, and per animal the
mean, SD and range over its frames (as biologists report repeated measurements).

The per-frame chain is the CLI's (core/measure/records.py): the measurement becomes an
annotation with the clip's camera and the frame's altitude, then ``estimate_baseline``.
"""

from collections.abc import Sequence
from dataclasses import dataclass, replace
from datetime import datetime, timedelta
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation_json import AnnotationFile
from dolphinfit.core.io.srt import parse_srt, srt_clock_start
from dolphinfit.core.io.telemetry import SRT_SUFFIX, Telemetry, find_srt_sidecar, load_telemetry
from dolphinfit.core.io.video import Clip
from dolphinfit.core.measure.annotation import Calibration
from dolphinfit.core.measure.baseline import BaselineEstimate, BaselineSettings, estimate_baseline
from dolphinfit.core.fit.config import FitConfig, fit_hw_table
from dolphinfit.core.measure.hw_ratios import HWRatios
from dolphinfit.core.measure.lens import through_lens
from dolphinfit.core.measure.records import (
    MeasureInput, default_error_model, measured_image_from_annotation, result_record,
    with_altitude_calibration,
)
from dolphinfit.core.measure.uncertainty import ErrorModel, Summary, length_summary
from dolphinfit.core.project.calibrations import clip_calibration
from dolphinfit.core.project.fit_settings import FitSettings, fit_config
from dolphinfit.core.project.model import ClipEntry, MeasurementKey, Project, get_measurement

# Per-animal summary: these result keys, over the animal's measured frames
SUMMARY_KEYS = ("length_m", "volume_m3", "bci", "density_kg_m3", "mass_kg")


def project_hw_spec(project: Project, project_dir: Path | None) -> str:
    """The project's HW table as ``resolve_hw`` takes it: a CSV path stored relative to the
    project file made absolute; a preset name (or "model") as it is."""
    spec = project.hw_ratios
    if project_dir is not None and spec.lower().endswith(".csv") and not Path(spec).is_absolute():
        return str(project_dir / spec)
    return spec


def project_fit_config(settings: FitSettings, project: Project,
                       project_dir: Path) -> FitConfig:
    """``fit_config`` with the project's HW table for the heights a top view cannot see, so
    that both methods take them from the same table."""
    return replace(fit_config(settings),
                   hw_table=fit_hw_table(project_hw_spec(project, project_dir)))


def clip_telemetry(project_dir: Path, clip: ClipEntry, media: Clip) -> Telemetry | None:
    """Altitude per frame of a clip from its AltitudeSpec; None when none was given."""
    spec = clip.altitude
    if spec is None:
        return None
    source = spec.constant_m if spec.path is None else project_dir / spec.path
    return load_telemetry(media, source, spec.launch_height_m, spec.time_offset_s)


def clip_clock_start(project_dir: Path, clip: ClipEntry, media: Clip) -> datetime | None:
    """The camera's local date-time at the clip's first frame, from its SRT: the altitude file
    when that is an SRT, else the SRT beside the media. None without one, or when it has no
    dates or cannot be read: the date is only a label, so it never stops a measurement."""
    spec = clip.altitude
    is_srt = (spec is not None and spec.path is not None
              and Path(spec.path).suffix.lower() == SRT_SUFFIX)
    path = project_dir / spec.path if is_srt else find_srt_sidecar(media.path)
    if path is None:
        return None
    try:
        return srt_clock_start(parse_srt(path))
    except InputError:
        return None


def frame_recorded_at(clock_start: datetime | None, telemetry: Telemetry,
                      frame_idx: int) -> datetime | None:
    """The local date-time of a frame: the clip's clock start plus the frame's time."""
    if clock_start is None:
        return None
    return clock_start + timedelta(seconds=float(telemetry.time_s[frame_idx]))


def frame_altitude(telemetry: Telemetry | None, frame_idx: int) -> float:
    """The altitude of one frame; InputError saying why when there is none."""
    if telemetry is None:
        raise InputError("no altitude for this clip: set one (Clip → Altitude…)")
    if not 0 <= frame_idx < telemetry.num_frames:
        raise InputError(f"frame {frame_idx} lies outside the altitude record")
    altitude = float(telemetry.altitude_m[frame_idx])
    if not np.isfinite(altitude) or altitude <= 0:
        raise InputError(f"no valid altitude at frame {frame_idx} "
                         f"({telemetry.source.describe()})")
    return altitude


def image_id(clip: ClipEntry, frame_idx: int) -> str:
    """The name a frame is exported under: the media's stem, plus the frame for a clip."""
    stem = Path(clip.media_path).stem
    return stem if clip.kind == "image" else f"{stem}_f{frame_idx:06d}"


@dataclass(frozen=True, eq=False)
class FrameResult:
    """The elliptical estimate of one measured frame and the records exported from it;
    ``recorded_at``: the camera's local date-time of the frame (None: unknown)."""

    key: MeasurementKey
    image_id: str
    source: MeasureInput
    estimate: BaselineEstimate
    record: dict
    recorded_at: datetime | None = None


def frame_annotation(project: Project, key: MeasurementKey, altitude_m: float,
                     altitude_source: str, media_path: str | None = None) -> AnnotationFile:
    """A measured frame as an annotation file: its clicks as clicked, the clip's camera, the
    recorded altitude, the export name as image ID; ``media_path``: the media relative to
    where the file goes (None: the clip's, relative to the project). InputError while the
    camera is unknown, ValueError while the frame has no length."""
    clip = project.clips[key.clip]
    camera = clip.known_camera()
    measurement = get_measurement(project, key)
    annotation = measurement.to_annotation()
    if annotation is None:
        raise ValueError("no body length yet: click from the rostrum tip to the fluke notch")
    return AnnotationFile(
        annotation=annotation,
        calibration=Calibration(camera, clip.preset_name, altitude_m, altitude_source),
        image_id=image_id(clip, measurement.frame_idx),
        media_path=clip.media_path if media_path is None else media_path,
        notes=measurement.notes)


def _frame_input(project: Project, key: MeasurementKey, altitude_m: float,
                 altitude_source: str) -> tuple[str, MeasureInput, ErrorModel]:
    """The frame's export name, its measurement in pixels with its camera and altitude (the
    clicks through the clip's lens model and its altitude calibration applied, where it has
    them) and the error SDs that go with them; InputError while the camera is unknown."""
    clip = project.clips[key.clip]
    doc = frame_annotation(project, key, altitude_m, altitude_source)
    name, camera = doc.image_id, doc.calibration.camera
    doc, notes, warnings = through_lens(doc, clip.lens, f"the lens model of {clip.name}")
    edge_sources = get_measurement(project, key).used_edge_sources()
    source = replace(measured_image_from_annotation(doc, image_id=name, notes=notes),
                     warnings=tuple(warnings), edge_sources=edge_sources)
    overrides = {}
    altitude_calibration = clip_calibration(project, key.clip)
    if altitude_calibration is not None:
        source = with_altitude_calibration(source, altitude_calibration, name)
        overrides = altitude_calibration.error_overrides(altitude_m)
    return name, source, default_error_model(altitude_source, camera.approximate,
                                             **overrides)


def measure_frame(project: Project, key: MeasurementKey, altitude_m: float,
                  altitude_source: str, hw: HWRatios, num_draws: int,
                  seed: int = 0, recorded_at: datetime | None = None) -> FrameResult:
    """The elliptical estimate of one measured frame (with ``num_draws`` Monte Carlo draws),
    taken at ``recorded_at`` (local camera time; None: unknown).

    Raises ValueError when the frame has no length yet, NoWidthError (a ValueError) when it
    has no width yet.
    """
    name, source, errors = _frame_input(project, key, altitude_m, altitude_source)
    settings = BaselineSettings(hw=hw, tail=project.tail)
    estimate = estimate_baseline(source.pixels, source.focal_px, source.record.altitude_m,
                                 settings, errors, num_draws, np.random.default_rng(seed))
    return FrameResult(key=key, image_id=name, source=source, estimate=estimate,
                       record=result_record(source, estimate, input_name=name, seed=seed),
                       recorded_at=recorded_at)


@dataclass(frozen=True, eq=False)
class LengthResult:
    """A measured frame with its length and no width yet: the length (m), the altitude and
    ground sampling distance, and with draws the length's Monte Carlo (None without)."""

    key: MeasurementKey
    image_id: str
    length_m: float
    altitude_m: float
    m_per_px: float
    interval: Summary | None


def measure_length(project: Project, key: MeasurementKey, altitude_m: float,
                   altitude_source: str, num_draws: int, seed: int = 0) -> LengthResult:
    """The length of a measured frame alone (``length_summary``); ValueError without one."""
    name, source, errors = _frame_input(project, key, altitude_m, altitude_source)
    altitude_m = source.record.altitude_m
    m_per_px = altitude_m / source.focal_px
    interval = None
    if num_draws > 0:
        interval = length_summary(source.pixels.length_px, source.focal_px, altitude_m, errors,
                                  num_draws, np.random.default_rng(seed))
    return LengthResult(key=key, image_id=name, length_m=source.pixels.length_px * m_per_px,
                        altitude_m=altitude_m, m_per_px=m_per_px, interval=interval)


@dataclass(frozen=True)
class Spread:
    """Mean, SD (n − 1; NaN for one frame), minimum and maximum over ``n`` frames."""

    n: int
    mean: float
    sd: float
    low: float
    high: float


def spread(values: Sequence[float]) -> Spread:
    """The spread of one quantity over frames."""
    array = np.asarray(values, dtype=np.float64)
    if array.size == 0:
        raise ValueError("no measured frame")
    return Spread(n=int(array.size), mean=float(array.mean()),
                  sd=float(array.std(ddof=1)) if array.size > 1 else float("nan"),
                  low=float(array.min()), high=float(array.max()))


def animal_summary(results: Sequence[FrameResult]) -> dict[str, Spread]:
    """Per quantity of SUMMARY_KEYS, its spread over one animal's frames."""
    return {key: spread([r.record[key] for r in results]) for key in SUMMARY_KEYS}
