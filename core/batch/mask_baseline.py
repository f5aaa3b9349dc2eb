"""The elliptical baseline of a manifest's animal, measured automatically on its masks: the
length midline and the 19 widths of the fitted frame where the mask is largest (the animal
flattest at the surface), as "suggest edges" places them in the app. Nobody reviews these
clicks: flippers joined to the outline near 25 % widen those stations."""

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from dolphinfit.core.batch.summary import elliptical_values
from dolphinfit.core.batch.task import MaskMeasurement
from dolphinfit.core.camera_presets import DEFAULT_PRESET, CameraPreset, get_preset
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.pipeline import CameraChoice, FitRun
from dolphinfit.core.measure.altitude_calibration import AltitudeCalibration
from dolphinfit.core.measure.annotation_json import AnnotationFile
from dolphinfit.core.measure.annotation import Calibration
from dolphinfit.core.measure.baseline import BaselineEstimate, BaselineSettings, estimate_baseline
from dolphinfit.core.model.hw_spec import resolve_hw
from dolphinfit.core.measure.lens import through_lens
from dolphinfit.core.measure.mask_midline import annotation_from_mask
from dolphinfit.core.measure.records import (
    MeasureInput, default_error_model, measured_image_from_annotation, result_record,
    write_exports,
)
from dolphinfit.core.project.results import frame_altitude

NOTE = "automatic: midline and widths from the mask, not reviewed"


def clip_camera(choice: CameraChoice, width_px: int,
                height_px: int) -> tuple[CameraPreset, str | None]:
    """The camera of ``choice`` at the clip's frame size (as CameraChoice.intrinsics) and its
    preset's name (None for explicit values)."""
    if choice.sensor_width_mm is not None and choice.focal_mm is not None:
        return CameraPreset(name="explicit", description="camera values of the batch",
                            focal_mm=choice.focal_mm, sensor_width_mm=choice.sensor_width_mm,
                            image_width_px=width_px, image_height_px=height_px,
                            source="batch manifest", approximate=False), None
    name = choice.preset or DEFAULT_PRESET
    return replace(get_preset(name), image_width_px=width_px, image_height_px=height_px), name


def largest_mask_frame(run: FitRun) -> int:
    """Of the fitted frames, the one with the most mask pixels."""
    frames = [int(f) for f in run.result.frame_idx]
    return max(frames, key=lambda f: int(run.masks.mask(f).sum()))


def _measured(run: FitRun, frame_idx: int, choice: CameraChoice,
              measurement: MaskMeasurement, altitude_calibration: AltitudeCalibration | None
              ) -> tuple[MeasureInput, BaselineEstimate, dict[str, Any], str]:
    """The elliptical measurement of one frame's mask: its input, estimate, record and image
    ID."""
    annotation = annotation_from_mask(run.masks.mask(frame_idx), frame_idx)
    clip = run.clip
    camera, preset_name = clip_camera(choice, clip.width_px, clip.height_px)
    calibration = Calibration(camera, preset_name, frame_altitude(run.telemetry, frame_idx),
                              measurement.altitude_source)
    image_id = f"{clip.path.stem}_f{frame_idx:06d}"
    doc = AnnotationFile(annotation=annotation, calibration=calibration, image_id=image_id,
                         media_path=str(clip.path), notes=NOTE)
    doc, lens_notes, warnings = through_lens(doc, measurement.lens, "the row's lens model")
    source = replace(measured_image_from_annotation(doc, image_id=image_id,
                                                    notes=[NOTE, *lens_notes]),
                     warnings=tuple(warnings))
    overrides = {}
    if altitude_calibration is not None:
        recorded = float(altitude_calibration.recorded_altitude(calibration.altitude_m))
        source = replace(source, recorded_altitude_m=recorded)
        overrides = altitude_calibration.error_overrides(recorded)
    estimate = estimate_baseline(
        source.pixels, source.focal_px, calibration.altitude_m,
        BaselineSettings(hw=resolve_hw(measurement.hw), tail=measurement.tail),
        default_error_model(source.altitude_source, source.is_camera_approximate, **overrides),
        measurement.num_draws, np.random.default_rng(0))
    return source, estimate, result_record(source, estimate, input_name=image_id, seed=0), \
        image_id


def mask_baseline(run: FitRun, choice: CameraChoice, measurement: MaskMeasurement,
                  stem: Path, altitude_calibration: AltitudeCalibration | None = None
                  ) -> tuple[dict[str, Any], BaselineEstimate, list[str]]:
    """Measure the animal on its masks and write STEM_measure.json, STEM_mmx.csv and
    STEM_wide.csv: on its largest fitted mask, or on each of ``measurement.frames`` where
    its mask shows it (each as STEM_IMAGEID_*), the summary's values then of the frame of
    median volume. The summary's elliptical values, their estimate and notes.
    ``altitude_calibration``: the one the fit's altitudes were corrected by, which then sets
    the altitude's error."""
    if not measurement.frames:
        frame_idx = largest_mask_frame(run)
        source, estimate, record, image_id = _measured(run, frame_idx, choice, measurement,
                                                       altitude_calibration)
        write_exports(stem, source, estimate, record)
        return elliptical_values(estimate, record, image_id, frame_idx), estimate, []
    masks = run.masks
    seen = [f for f in measurement.frames if 0 <= f < masks.num_frames and masks.is_visible[f]]
    notes: list[str] = []
    measured = []
    for frame_idx in seen:
        try:
            source, estimate, record, image_id = _measured(run, frame_idx, choice, measurement,
                                                           altitude_calibration)
        except (InputError, ValueError) as exc:  # e.g. no altitude on that frame
            notes.append(f"frame {frame_idx} not measured: {exc}")
            continue
        write_exports(stem.with_name(f"{stem.name}_{image_id}"), source, estimate, record)
        measured.append((float(estimate.point.volume_m3), frame_idx, estimate, record,
                         image_id))
    if not measured:
        raise InputError("no frame to measure: " + ("; ".join(notes) or
                         "the masks lost the animal on every one "
                         f"({', '.join(map(str, measurement.frames))})"))
    measured.sort(key=lambda item: item[0])
    _, frame_idx, estimate, record, image_id = measured[(len(measured) - 1) // 2]
    volumes = [item[0] for item in measured]
    notes.insert(0, f"elliptical of frame {frame_idx}, the median volume of {len(measured)} "
                    f"best frames ({min(volumes):.4f}–{max(volumes):.4f} m³)")
    lost = sorted(set(measurement.frames) - set(seen))
    if lost:
        notes.append(f"the masks lost the animal on frames {', '.join(map(str, lost))}")
    return elliptical_values(estimate, record, image_id, frame_idx), estimate, notes
