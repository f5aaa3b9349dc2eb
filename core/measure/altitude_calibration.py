"""Altitude calibration from an object of known length photographed at recorded altitudes.

An object ``L`` metres long that measures ``p`` pixels in an image from a camera of focal length
``f`` pixels lies at ``H = L f / p`` metres below it: the altitude the image itself says. Over
many images, this implied altitude against the recorded one is a straight line,

    H_true = a + b · H_recorded,

fitted by ordinary least squares. ``a`` is the altimeter's offset and ``b`` its scale together
with any error of the camera's stated focal length and sensor width (a video mode that crops
the sensor shows up as ``b`` ≠ 1): the calibration holds for the camera it was made with. This
is MedidoR's model (``lm(eGSD ~ C_Alt)``: the metres per pixel are ``H / f``, so its
coefficients are ours divided by ``f``) and the last step of CollatriX v1's ``altitude_calib``
(Burnett et al. 2018, method 5, which first smooths the pixel lengths on a log-log line).
Xcertainty's altimeter model (Bierlich et al. 2021) is an additive bias with the camera taken as
stated; its estimate ``mean(H_recorded − H)`` is reported beside ours for comparison.

The spread of the implied altitudes about the line, as a share of the altitude, becomes the
altitude's SD in the intervals. It holds the digitisation error of the object's ends as well as
the altimeter's: an upper bound on the altimeter's own error, which is the safe side.
"""

from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.calibration_table import CalibrationTable
from dolphinfit.core.io.json_file import read_tagged_dataclass, write_json
from dolphinfit.core.io.telemetry import Telemetry
from dolphinfit.core.limits import (
    BODY_LENGTH_M, FOCAL_MM, IMAGE_SIZE_PX, SENSOR_WIDTH_MM, in_range,
)

FORMAT = "dolphinfit-altitude-calibration"
VERSION = 1
MIN_SHOTS = 5
MIN_ALTITUDE_SPAN = 1.25     # highest over lowest recorded altitude: less cannot part a from b
OUTLIER_SDS = 3.0            # residuals beyond this many SDs are named as probable mis-clicks
SAME_CAMERA_RTOL = 1e-6
FOCAL_PX_RTOL = 1e-3         # a preset's rounding, not another lens or video mode
CONFIDENCE = 0.95


def same_focal_px(a_px: float, b_px: float) -> bool:
    """Whether two focal lengths in pixels are one camera and video mode's (a calibration
    made with one holds for the other)."""
    return bool(np.isclose(a_px, b_px, rtol=FOCAL_PX_RTOL, atol=0.0))


@dataclass(frozen=True)
class CalibrationCamera:
    """The camera the calibration holds for: real focal length, read sensor width, image
    width (what fixes the pixels' size on the water)."""

    focal_mm: float
    sensor_width_mm: float
    image_width_px: int

    @property
    def focal_px(self) -> float:
        return self.focal_mm * self.image_width_px / self.sensor_width_mm

    def text(self) -> str:
        return (f"focal {self.focal_mm:g} mm, sensor {self.sensor_width_mm:g} mm, "
                f"{self.image_width_px} px wide")


@dataclass(frozen=True)
class AltitudeCalibration:
    """A fitted line from recorded to true altitude for one drone, altimeter and camera."""

    drone: str
    altimeter: str                   # the table's altitude column
    camera: CalibrationCamera
    object_length_m: float
    num_shots: int
    recorded_range_m: tuple[float, float]
    intercept_m: float               # a
    slope: float                     # b
    intercept_ci_m: tuple[float, float]   # 95 %
    slope_ci: tuple[float, float]
    intercept_se_m: float
    slope_se: float
    mean_recorded_m: float           # where the line's two errors are uncorrelated
    residual_sd_m: float
    residual_sd_fraction: float      # of the altitude: the altitude SD it gives intervals
    bias_only_m: float               # Xcertainty's model: mean(recorded − implied)
    bias_only_sd_m: float
    outliers: tuple[str, ...]        # images whose residual exceeds OUTLIER_SDS SDs
    source: str                      # the table's file name

    def true_altitude(self, recorded_m: float | np.ndarray) -> float | np.ndarray:
        """The calibrated altitude of a recorded one."""
        return self.intercept_m + self.slope * recorded_m

    def recorded_altitude(self, true_m: float | np.ndarray) -> float | np.ndarray:
        """The recorded altitude a calibrated one came from."""
        return (true_m - self.intercept_m) / self.slope

    def altitude_sd_fraction(self, recorded_m: float) -> float:
        """The SD of one image's calibrated altitude as a share of it: the shots' spread about
        the line and the line's own standard error there (a prediction for a new image)."""
        centred = recorded_m - self.mean_recorded_m
        # intercept and slope covary by −mean × slope SE²; at the mean they are independent
        line_var = (self.intercept_se_m ** 2 - self.mean_recorded_m ** 2 * self.slope_se ** 2
                    + centred ** 2 * self.slope_se ** 2)
        return float(np.hypot(self.residual_sd_fraction,
                              np.sqrt(max(line_var, 0.0)) / self.true_altitude(recorded_m)))

    def error_overrides(self, recorded_m: float) -> dict[str, float]:
        """The ``ErrorModel`` fields this calibration sets for an image recorded at
        ``recorded_m``: its altitude SD, and no separate error of the focal length (the line
        absorbed the camera's scale)."""
        return {"altitude_sd_fraction": self.altitude_sd_fraction(recorded_m),
                "focal_sd_fraction": 0.0}

    def check_focal_px(self, focal_px: float, where: str) -> None:
        """InputError naming ``where`` unless its camera has the calibrated focal length in
        pixels (what ties pixels to metres; a video mode that crops differently has another)."""
        if not same_focal_px(focal_px, self.camera.focal_px):
            raise InputError(f"{where}: the altitude calibration was made with a camera of "
                             f"focal length {self.camera.focal_px:.1f} px ({self.camera.text()}); "
                             f"this one has {focal_px:.1f} px: a calibration holds only for its "
                             f"own camera and video mode")

    def extrapolation_warning(self, recorded_m: float) -> str | None:
        """A warning when ``recorded_m`` lies outside the calibrated altitudes."""
        low, high = self.recorded_range_m
        if low <= recorded_m <= high:
            return None
        return (f"recorded altitude {recorded_m:g} m lies outside the calibrated "
                f"{low:g}–{high:g} m: the line is extrapolated")

    def to_json(self) -> dict:
        return {"format": FORMAT, "version": VERSION, **asdict(self)}


def calibrated_telemetry(telemetry: Telemetry, calibration: AltitudeCalibration) -> Telemetry:
    """``telemetry`` at calibrated altitudes (missing ones stay missing), with a warning when
    some lie outside the calibrated range."""
    recorded = telemetry.altitude_m[np.isfinite(telemetry.altitude_m)]
    warnings = [warning for value in ((recorded.min(), recorded.max()) if recorded.size else ())
                if (warning := calibration.extrapolation_warning(float(value))) is not None]
    return replace(telemetry, altitude_m=calibration.true_altitude(telemetry.altitude_m),
                   warnings=(*telemetry.warnings, *dict.fromkeys(warnings)))


def _one_value(table: CalibrationTable, name: str, given: float | None, label: str,
               option: str) -> float:
    """The one value of the table's shot field ``name``, or ``given``: InputError when the
    table's rows disagree with each other (CalibrationTable.common_value) or with ``given``,
    or neither says."""
    if given is not None:
        known = table.known_values(name)
        if known.size and not np.allclose(known, given, rtol=SAME_CAMERA_RTOL, atol=0.0):
            listed = ", ".join(f"{value:g}" for value in np.unique(known))
            raise InputError(f"{table.path}: the table's {label} ({listed}) differs from "
                             f"{option} {given:g}")
        return float(given)
    value = table.common_value(name, f"the {label}")
    if value is None:
        raise InputError(f"{table.path}: the table has no {label}; give {option}")
    return value


def calibration_inputs(table: CalibrationTable, object_length_m: float | None,
                       camera: CalibrationCamera | None) -> tuple[float, CalibrationCamera]:
    """The object's length and the camera, from the options or the table (which must agree)."""
    length = _one_value(table, "object_length_m", object_length_m, "object length",
                        "--object-length")
    in_range(length, BODY_LENGTH_M, "--object-length")
    options = ("--focal-mm", "--sensor-width-mm", "--image-width")
    values = [_one_value(table, name, None if camera is None else getattr(camera, name),
                         name.replace("_", " "), option)
              for name, option in zip(("focal_mm", "sensor_width_mm", "image_width_px"),
                                      options)]
    for value, limits, option in zip(values, (FOCAL_MM, SENSOR_WIDTH_MM, IMAGE_SIZE_PX),
                                     options):
        in_range(value, limits, option)
    return length, CalibrationCamera(values[0], values[1], int(round(values[2])))


def fit_altitude_calibration(table: CalibrationTable, object_length_m: float | None = None,
                             camera: CalibrationCamera | None = None) -> AltitudeCalibration:
    """The least-squares line of implied on recorded altitude (module doc) and its spread.

    InputError when there are fewer than ``MIN_SHOTS`` shots or their recorded altitudes span
    too little to part offset from scale."""
    from scipy import stats

    length, camera = calibration_inputs(table, object_length_m, camera)
    shots, path = table.shots, table.path
    if len(shots) < MIN_SHOTS:
        raise InputError(f"{path}: {len(shots)} usable shots; a calibration needs at least "
                         f"{MIN_SHOTS} at several altitudes")
    recorded = np.array([s.recorded_altitude_m for s in shots])
    implied = length * camera.focal_px / np.array([s.pixel_length for s in shots])
    low, high = float(recorded.min()), float(recorded.max())
    if high < MIN_ALTITUDE_SPAN * low:
        raise InputError(f"{path}: the recorded altitudes span only {low:g}–{high:g} m; "
                         f"photograph the object over a wider range (the highest at least "
                         f"{MIN_ALTITUDE_SPAN:g}× the lowest) to tell offset from scale")
    line = stats.linregress(recorded, implied)
    t = stats.t.ppf(0.5 + CONFIDENCE / 2, len(shots) - 2)
    predicted = line.intercept + line.slope * recorded
    residual = implied - predicted
    residual_sd = float(np.sqrt(np.sum(residual ** 2) / (len(shots) - 2)))
    relative = implied / predicted - 1   # about the line, as the residuals: no mean taken off
    outlying = np.abs(residual) > OUTLIER_SDS * residual_sd
    offsets = recorded - implied
    return AltitudeCalibration(
        drone=table.drone, altimeter=table.altimeter_column, camera=camera,
        object_length_m=length, num_shots=len(shots), recorded_range_m=(low, high),
        intercept_m=float(line.intercept), slope=float(line.slope),
        intercept_ci_m=(float(line.intercept - t * line.intercept_stderr),
                        float(line.intercept + t * line.intercept_stderr)),
        slope_ci=(float(line.slope - t * line.stderr), float(line.slope + t * line.stderr)),
        intercept_se_m=float(line.intercept_stderr), slope_se=float(line.stderr),
        mean_recorded_m=float(recorded.mean()),
        residual_sd_m=residual_sd,
        residual_sd_fraction=float(np.sqrt(np.sum(relative ** 2) / (len(shots) - 2))),
        bias_only_m=float(offsets.mean()), bias_only_sd_m=float(offsets.std(ddof=1)),
        outliers=tuple(s.image for s, out in zip(shots, outlying) if out),
        source=path.name)


def read_altitude_calibration(path: Path | str) -> AltitudeCalibration:
    """A calibration written by ``dolphinfit calibrate altitude``; InputError naming the file
    and field when it is not one or a value is impossible."""
    path = Path(path)
    calibration = read_tagged_dataclass(path, AltitudeCalibration, FORMAT, VERSION,
                                        "altitude calibration")
    camera = calibration.camera
    numbers = (calibration.intercept_m, calibration.slope, calibration.residual_sd_fraction,
               camera.focal_mm, camera.sensor_width_mm, camera.image_width_px)
    if not (all(np.isfinite(numbers)) and calibration.slope > 0
            and calibration.residual_sd_fraction >= 0 and min(numbers[3:]) > 0):
        raise InputError(f"{path}: the slope, residual SD and camera must be positive numbers "
                         f"(slope {calibration.slope!r}, residual SD fraction "
                         f"{calibration.residual_sd_fraction!r}, {camera.text()})")
    return calibration


def write_altitude_calibration(calibration: AltitudeCalibration, path: Path) -> None:
    """``path`` as JSON, written atomically."""
    write_json(path, calibration.to_json())
