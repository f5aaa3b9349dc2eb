"""One measured image as records: its inputs, the result JSON, the table rows, the exports.

The CLI (`dolphinfit measure`) and the GUI build the same records with these functions:

1. a :class:`MeasureInput` from an annotation (:func:`measured_image_from_annotation`) or a
   MorphoMetriX CSV (:func:`measured_image_from_morphometrix`);
2. ``core.measure.baseline.estimate_baseline`` on its pixels, focal length and altitude;
3. :func:`result_record` (the result JSON), then :func:`write_exports`: STEM_measure.json,
   STEM_mmx.csv (MorphoMetriX v2, long, or v1, blocks), STEM_wide.csv (ours: metres, pixels,
   Xcertainty's calibration and the results, one row) and STEM_collatrix.csv (the row
   CollatriX's body-condition tool reads as it is; core.measure.collatrix).
"""

from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation_json import AnnotationFile
from dolphinfit.core.measure.collatrix import collatrix_row, wide_row, write_wide_csv
from dolphinfit.core.io.json_file import read_json, write_json
from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.measure.morphometrix import (
    LENGTH_NAME, MorphoMetrixRecord, read_morphometrix, record_from_pixels, total_length_name,
    write_morphometrix,
)
from dolphinfit.core.measure.morphometrix import pixel_measurements as record_pixels
from dolphinfit.core.measure.altitude_calibration import AltitudeCalibration
from dolphinfit.core.measure.annotation import (
    PixelMeasurements, pixel_measurements, place_stations,
)
from dolphinfit.core.measure.baseline import SUMMARISED, BaselineEstimate
from dolphinfit.core.measure.condition import MassModel
from dolphinfit.core.measure.edge_sources import stations_sources_json, wide_source_columns
from dolphinfit.core.measure.elliptical import TAIL_EXTRAPOLATED, TAIL_MEASURED, fill_skipped
from dolphinfit.core.measure.mask_midline import suggested_edges
from dolphinfit.core.measure.stations import STATION_PCT
from dolphinfit.core.measure.uncertainty import ErrorModel

RESULT_SCHEMA_VERSION = 1
MMX_ALTITUDE_SOURCE = "manual"  # MorphoMetriX altitudes are typed in; the source is unknown
# appended to the export stem
EXPORT_SUFFIXES = ("_measure.json", "_mmx.csv", "_wide.csv", "_collatrix.csv")


@dataclass(frozen=True)
class MeasureInput:
    """One measured image brought to pixels, calibration and export metadata."""

    pixels: PixelMeasurements
    record: MorphoMetrixRecord      # metadata and measurements as exported
    focal_px: float
    altitude_source: str
    is_camera_approximate: bool
    notes: list[str]                # for the user, one line each
    image_width_px: int | None = None   # Xcertainty's Iw, Sw and uas (annotations only)
    sensor_width_mm: float | None = None
    uas: str = ""
    recorded_altitude_m: float | None = None   # before an altitude calibration, if applied
    warnings: tuple[str, ...] = ()   # about the input (added to the estimate's in the result)
    edge_sources: np.ndarray | None = None   # (S, 2) core.measure.edge_sources; None: unknown


def default_image_id(doc: AnnotationFile, path: Path) -> str:
    """The annotation's image ID, else "<file stem> frame <index>"."""
    return doc.image_id or f"{path.stem} frame {doc.annotation.frame_idx}"


def annotated_frame_mask(masks: Path, doc: AnnotationFile) -> np.ndarray:
    """(H, W) bool mask of the annotated frame from a mask source (core.io.masks formats).

    InputError naming ``masks`` when its size is not the camera's or the frame has no dolphin.
    """
    camera, frame_idx = doc.calibration.camera, doc.annotation.frame_idx
    track = read_masks(masks)
    if (track.height_px, track.width_px) != (camera.image_height_px, camera.image_width_px):
        raise InputError(f"{masks}: masks are {track.width_px}×{track.height_px} px but the "
                         f"camera's frames are {camera.image_width_px}×{camera.image_height_px}"
                         f" px")
    if not (0 <= frame_idx < track.num_frames and track.is_visible[frame_idx]):
        raise InputError(f"{masks}: no dolphin in the mask of frame {frame_idx}")
    return track.mask(frame_idx)


def with_mask_widths(doc: AnnotationFile, mask: np.ndarray) -> AnnotationFile:
    """``doc`` with each station's edges where its perpendicular leaves ``mask`` (H, W), the
    flipper stations' without the flippers (``mask_midline.suggested_edges``)."""
    annotation = doc.annotation
    edges = suggested_edges(mask, place_stations(annotation.midline_px))
    return replace(doc, annotation=replace(annotation, edges_px=edges))


def measured_image_from_annotation(doc: AnnotationFile, *, image_id: str,
                                   notes: list[str] | None = None) -> MeasureInput:
    """The calibrated pixels, MorphoMetriX record and Xcertainty fields of an annotated frame.

    ``notes`` are appended to the line naming the frame and camera.
    """
    annotation, calibration = doc.annotation, doc.calibration
    camera = calibration.camera
    pixels = pixel_measurements(annotation)
    record = record_from_pixels(
        pixels, image_id=image_id, image_path=doc.media_path, focal_mm=camera.focal_mm,
        pixel_dimension_mm=camera.sensor_width_mm / camera.image_width_px,
        altitude_m=calibration.altitude_m, mirror_side=annotation.mirror_side, notes=doc.notes)
    return MeasureInput(
        pixels=pixels, record=record, focal_px=calibration.focal_px,
        altitude_source=calibration.altitude_source, is_camera_approximate=camera.approximate,
        notes=[f"frame {annotation.frame_idx}, camera {calibration.preset_name or 'explicit'}"
               f" (focal {calibration.focal_px:.1f} px)", *(notes or [])],
        image_width_px=camera.image_width_px, sensor_width_mm=camera.sensor_width_mm,
        uas=calibration.preset_name or "")


def measured_image_from_morphometrix(path: Path, *, altitude_m: float | None = None,
                                     altitude_source: str | None = None,
                                     length_name: str | None = None) -> MeasureInput:
    """The pixels and metadata of a MorphoMetriX v1/v2 CSV.

    ``altitude_m`` replaces the file's altitude (the pixels stay those of the file's altitude);
    without ``altitude_source`` the source is taken as MMX_ALTITUDE_SOURCE, with a note.
    ``length_name``: the total length's name in the file (default: TL, Total_Length, …,
    morphometrix.total_length_name); the exports name it LENGTH_NAME, so that measurements
    from several labs pool under the same columns.
    """
    record = read_morphometrix(path)
    length_name = total_length_name(record, path, length_name)
    pixels = record_pixels(record, path, length_name)
    if altitude_m is not None:
        record = replace(record, altitude_m=altitude_m)
    notes = [f"MorphoMetriX v{record.version} file, focal {record.focal_px:.1f} px"]
    if length_name != LENGTH_NAME:
        notes.append(f"total length {length_name!r} exported as {LENGTH_NAME}")
    if altitude_source is None:
        notes.append(f"altitude source unknown: taken as {MMX_ALTITUDE_SOURCE}")
    if record.version == 1:
        notes.append("v1 files hold rounded metres only: pixels derived from them")
    if pixels.is_mirrored:
        notes.append("mirror-side widths: MorphoMetriX v2 may store one side undoubled; check")
    exported = record_from_pixels(
        pixels, image_id=record.image_id, image_path=record.image_path,
        focal_mm=record.focal_mm, pixel_dimension_mm=record.pixel_dimension_mm,
        altitude_m=record.altitude_m, mirror_side=record.mirror_side, notes=record.notes)
    return MeasureInput(pixels=pixels, record=exported, focal_px=record.focal_px,
                        altitude_source=altitude_source or MMX_ALTITUDE_SOURCE,
                        is_camera_approximate=False, notes=notes)


def mass_model_from_json(path: Path) -> MassModel:
    """The paper's mass-model constants overridden by a JSON object's entries."""
    data = read_json(path, "the mass model")
    names = {f.name for f in fields(MassModel)}
    if not isinstance(data, dict) or not set(data) <= names:
        raise InputError(f"{path}: expected an object with keys among {', '.join(sorted(names))}")
    if isinstance(data.get("bci_fit_range"), list):
        data["bci_fit_range"] = tuple(data["bci_fit_range"])
    try:
        return MassModel(**data)
    except (TypeError, ValueError, InputError) as exc:
        raise InputError(f"{path}: {exc}") from exc


def with_altitude_calibration(source: MeasureInput, calibration: AltitudeCalibration,
                              where: str) -> MeasureInput:
    """``source`` at its calibrated altitude (InputError naming ``where`` when its camera is
    not the calibrated one), with a note saying so and one when the line is extrapolated."""
    calibration.check_focal_px(source.focal_px, where)
    recorded = source.record.altitude_m
    altitude = float(calibration.true_altitude(recorded))
    notes = [f"altitude {recorded:g} m recorded → {altitude:.2f} m by the calibration from "
             f"{calibration.source}"]
    warning = calibration.extrapolation_warning(recorded)
    notes += [] if warning is None else [warning]
    return replace(source, record=replace(source.record, altitude_m=altitude),
                   recorded_altitude_m=recorded, notes=[*source.notes, *notes])


def default_error_model(altitude_source: str, is_camera_approximate: bool,
                        **overrides: float) -> ErrorModel:
    """The documented error SDs for an altitude source and camera, with ``overrides`` (ErrorModel
    field names) replacing some."""
    return replace(ErrorModel.default(altitude_source, is_camera_approximate), **overrides)


def result_record(source: MeasureInput, estimate: BaselineEstimate, *, input_name: str,
                  seed: int) -> dict:
    """The result JSON: schema version, input, calibration, Monte Carlo seed and the estimate
    (its warnings after the input's own; its stations with their edges' sources, where
    known)."""
    estimated = estimate.to_json()
    if source.edge_sources is not None:
        estimated["stations"] = [
            {**station, **sources} for station, sources in
            zip(estimated["stations"], stations_sources_json(source.edge_sources))]
    return {"schema_version": RESULT_SCHEMA_VERSION, "input": input_name,
            "altitude_m": source.record.altitude_m, "altitude_source": source.altitude_source,
            **({} if source.recorded_altitude_m is None
               else {"recorded_altitude_m": source.recorded_altitude_m}),
            "focal_px": source.focal_px, "seed": seed, **estimated,
            "warnings": [*source.warnings, *estimated["warnings"]]}


def wide_csv_row(source: MeasureInput, estimate: BaselineEstimate, result: dict, *,
                 csv_name: str) -> dict[str, str]:
    """Our wide-table row: measurements, calibration, the edges' sources (where known) and the
    result columns.

    ``csv_name``: the MorphoMetriX file exported with it.
    """
    sources = ({} if source.edge_sources is None
               else wide_source_columns(source.edge_sources, LENGTH_NAME))
    return wide_row(source.record, csv_name=csv_name, altitude_source=source.altitude_source,
                    image_width_px=source.image_width_px,
                    sensor_width_mm=source.sensor_width_mm, uas=source.uas,
                    extras={**sources, **_result_columns(estimate, result)})


def collatrix_csv_row(source: MeasureInput, estimate: BaselineEstimate, *, csv_name: str,
                      image_id: str | None = None) -> dict[str, str]:
    """The CollatriX-table row: metres, every station's width and the HW ratios used.

    Unmeasured stations get the interpolation the volume uses (from every measured width), so
    that CollatriX's elliptical volume of the row is ours under the extrapolated tail.
    ``csv_name``: the MorphoMetriX file exported with it; ``image_id`` replaces the record's
    (where several animals share an image, CollatriX needs ``Image_ID`` to tell them apart).
    """
    filled_px, is_filled = fill_skipped(estimate.measured.widths_px, TAIL_MEASURED)
    widths_m = dict(zip(STATION_PCT.tolist(), (filled_px * estimate.m_per_px).tolist()))
    record = replace(source.record, widths_m={**source.record.widths_m, LENGTH_NAME: widths_m})
    if image_id is not None:
        record = replace(record, image_id=image_id)
    ratios, _ = estimate.settings.hw.completed()
    return collatrix_row(record, csv_name=csv_name,
                         hw_ratios=dict(zip(STATION_PCT.tolist(), ratios.tolist())),
                         filled_pct=STATION_PCT[is_filled].tolist())


def write_exports(stem: Path, source: MeasureInput, estimate: BaselineEstimate,
                  result: dict, mmx_version: int = 2) -> list[Path]:
    """Write STEM_measure.json, STEM_mmx.csv (MorphoMetriX ``mmx_version``: 2 long, 1
    blocks), STEM_wide.csv and STEM_collatrix.csv; their paths."""
    paths = [stem.with_name(f"{stem.name}{suffix}") for suffix in EXPORT_SUFFIXES]
    write_json(paths[0], result)
    write_morphometrix(paths[1], source.record, mmx_version)
    write_wide_csv(paths[2], [wide_csv_row(source, estimate, result, csv_name=paths[1].name)])
    write_wide_csv(paths[3], [collatrix_csv_row(source, estimate, csv_name=paths[1].name)])
    return paths


def _result_columns(estimate: BaselineEstimate, result: dict) -> dict[str, object]:
    """Wide-CSV result columns: HW ratios used (CollatriX names), values and intervals."""
    ratios, _ = estimate.settings.hw.completed()
    columns: dict[str, object] = {f"{LENGTH_NAME}_ratio{pct:.2f}": float(r)
                                  for pct, r in zip(STATION_PCT, ratios)}
    columns.update({"tail": estimate.settings.tail, "hw_ratios": estimate.settings.hw.name})
    if estimate.settings.tail == TAIL_EXTRAPOLATED:
        columns["BVell_5perc"] = result["volume_m3"]  # CollatriX's elliptical volume, same method
    columns.update({name: result[name] for name in ("surface_area_m2",
                                                    "surface_area_parabola_m2")})
    for name in SUMMARISED:
        columns[name] = result[name]
        if estimate.interval is not None:
            s = getattr(estimate.interval, name)
            columns.update({f"{name}_sd": float(s.sd), f"{name}_lo95": float(s.low),
                            f"{name}_hi95": float(s.high)})
    return columns
