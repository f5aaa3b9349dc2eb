"""Part 5 of ``dolphinfit bench real``: the 3D fit on the real minke still against the two
people who measured it (the product's default fit, from our mask of a click on the back; the
camera and altitude of their CSV). A still shows one frame: the fit has no motion to tell a
pitched or bent body from a shorter one, which the people, measuring the outline as it lies,
do not ask either. Slow (minutes at the image's 2978 px), so not among the default parts."""

import time

import numpy as np

from dolphinfit.core.bench.real_data import MinkeImage
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.interval import run_interval
from dolphinfit.core.fit.pipeline import fit_clip
from dolphinfit.core.io.media import open_media
from dolphinfit.core.io.telemetry import constant_telemetry
from dolphinfit.core.measure.records import default_error_model
from dolphinfit.core.model.hw_from_model import station_extents
from dolphinfit.core.model.template import load_template
from dolphinfit.core.segment.backends import make_segmenter
from dolphinfit.core.segment.segmenter import PointSeed


def fit_minke(minke: MinkeImage, backend: str, config: FitConfig = FitConfig()) -> dict:
    """The fit's length, volume and mass with their 95 % intervals; its length and widths
    against each person's, and whether the length interval holds each person's length."""
    start = time.perf_counter()
    calibration, camera = minke.calibration, minke.calibration.camera
    with open_media(minke.image) as frames:
        clip = frames.clip
        masks = make_segmenter(backend).segment(frames, PointSeed(*minke.click_px))
        run = fit_clip(frames, constant_telemetry(calibration.altitude_m, clip), masks,
                       camera.intrinsics(), config)  # the camera is at the image's size
    result = run.result
    interval = run_interval(run, default_error_model(calibration.altitude_source,
                                                     camera.approximate))
    widths, _ = station_extents(result.rest_verts, load_template().station_rings)
    low, high = float(interval.length_m.low), float(interval.length_m.high)
    people = []
    for human in minke.humans:
        theirs = human.station_widths()
        measured = np.isfinite(theirs)
        people.append({
            "source": human.source, "length_m": human.length_m,
            "length_error_share": result.length_m / human.length_m - 1,
            "length_in_interval": low <= human.length_m <= high,
            "median_width_error_share": float(np.median(np.abs(
                widths[measured] / theirs[measured] - 1)))})
    return {"status": result.status, "reasons": list(result.reasons),
            "length_m": result.length_m,
            "volume_m3": result.volume_m3, "mass_kg": result.mass_kg,
            "interval": {key: {"low": float(getattr(interval, key).low),
                               "high": float(getattr(interval, key).high)}
                         for key in ("length_m", "volume_m3", "mass_kg")},
            "altitude_source": calibration.altitude_source,
            "outline_sd_px": interval.outline_sd_px, "mean_iou": float(result.iou.mean()),
            "widths_m": widths.tolist(), "people": people,
            "seconds": time.perf_counter() - start}
