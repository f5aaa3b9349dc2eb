"""``dolphinfit bench masks --sweep``: where our masks' outline lies as the picture changes.

One family of short clips (``core.synth``: a light-grey animal over blue water in a calm sea,
720p delivered, 15 m, about 25 px wide), each point changing one thing from the base: the
optics' blur σ, the body's contrast to the water in grey levels (dark over dark and light over
light too), sensor noise, H.264 at a constant rate factor, the frame delivered at 1×, 2× or 4×
below what was filmed (5K filmed, 720p delivered), and the animal's width in pixels (the
altitude). A point where the generator sees no animal (its mean contrast under
``core.synth.compose.VISIBLE_CONTRAST``) is reported as not visible. Each mask back-end tracks
the animal from a click on its first frame (where it finds none there, its masks are empty and
the point says why); every
``STRIDE``-th frame is scored against the true masks: the mean outline offset (px, + outside),
the IoU, and the error of the elliptical volume our masks give (length and 19 widths as
"suggest edges" places them, the default HW table) against the same measured on the true
masks: what the masks alone do to a volume.

The contrast points scale the animal's difference from the water (``body_contrast``) to
reach the grey levels asked for, from the base clip's own contrast, measured as the mean
grey level just inside the true outline against just outside (1–3 px from it).
"""

from collections.abc import Callable
from dataclasses import dataclass, replace

import cv2
import numpy as np

from dolphinfit.core.bench.mask_bench import click_seed, timed_pass
from dolphinfit.core.bench.scan_bench import elliptical_error
from dolphinfit.core.bench.scenario import synth_camera
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.whole_body import widest_px
from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.io.masks import MaskTrack, read_masks
from dolphinfit.core.io.telemetry import load_telemetry
from dolphinfit.core.io.video import VideoReader, open_clip
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.segment.backends import make_segmenter
from dolphinfit.core.segment.evaluate import outline_offset_px
from dolphinfit.core.synth.config import Effects, SynthConfig
from dolphinfit.core.synth.files import ClipFiles
from dolphinfit.core.synth.sample import cache_dir, ensure_clip
from dolphinfit.core.synth.water import with_water

SWEEP_SUITE = "bench-sweep-v1"
STRIDE = 4
BASE = with_water(SynthConfig(
    seed=701, width_px=1280, height_px=720, fps=10.0, duration_s=1.2, altitude_m=15.0,
    length_m=2.5, heading_deg=30.0, speed_m_s=1.2, shape_sd=0.05, colouration="light_grey",
    sea_state=0.1, glitter=0.0, splash=0.0, wet_specular=0.0, blur_px=0.6, noise_sd=0.01,
    dive_depth_m=0.15, codec="h264", crf=18, effects=Effects(finer_mesh=True)), "blue")
CONTRASTS = (5, 10, 20, 40, 60)        # grey levels, body against water
RING_PX = (1, 3)


@dataclass(frozen=True)
class SweepPoint:
    """One point of the sweep: what it changes, its value, and its clip's configuration
    (``contrast`` points get their ``body_contrast`` from the base clip's measured contrast)."""

    factor: str
    value: str
    config: SynthConfig
    contrast_levels: float | None = None


def sweep_points() -> tuple[SweepPoint, ...]:
    """The sweep's points (module doc), the base first."""
    points = [SweepPoint("base", "calm, light grey over blue", BASE)]
    points += [SweepPoint("blur", f"σ {sigma} px", replace(BASE, blur_px=sigma))
               for sigma in (0.3, 1.0, 1.5, 2.0)]
    points += [SweepPoint("contrast", f"{levels} grey levels", BASE, float(levels))
               for levels in CONTRASTS]
    points += [SweepPoint("contrast", "dark over dark",
                          with_water(replace(BASE, colouration="dark"), "ocean")),
               SweepPoint("contrast", "light over light", with_water(BASE, "turquoise"))]
    points += [SweepPoint("noise", f"SD {noise}", replace(BASE, noise_sd=noise))
               for noise in (0.0, 0.03)]
    points += [SweepPoint("compression", f"H.264 CRF {crf}", replace(BASE, crf=crf))
               for crf in (23, 28, 35)]
    points += [SweepPoint("delivered", f"filmed at {k}×", replace(BASE, supersample=k))
               for k in (2, 4)]
    points += [SweepPoint("width", f"{altitude:g} m", replace(BASE, altitude_m=altitude))
               for altitude in (48.0, 32.0, 10.0, 6.5)]
    return tuple(points)


def bench_sweep(backends: tuple[str, ...], progress: Callable[[dict], None] | None = None
                ) -> dict:
    """Every point with every back-end (module doc); ``progress(row)`` after each point."""
    base_contrast = None
    rows = []
    for number, point in enumerate(sweep_points()):
        config = point.config
        if point.contrast_levels is not None:
            if base_contrast is None:
                base_contrast = _contrast_levels(_ensure(sweep_points()[0], 0))
            config = replace(config, body_contrast=min(2.0, point.contrast_levels
                                                       / base_contrast))
        files = _ensure(replace(point, config=config), number)
        row = {"factor": point.factor, "value": point.value}
        if _truth(files)[1]:
            row.update(visible=True, contrast_levels=_contrast_levels(files), **_width(files),
                       backends={backend: _scores(files, config, backend)
                                 for backend in backends})
        else:
            row.update(visible=False, body_contrast=config.body_contrast)
        rows.append(row)
        if progress is not None:
            progress(row)
    return {"points": rows, "stride": STRIDE, "suite": SWEEP_SUITE}


def _ensure(point: SweepPoint, number: int) -> ClipFiles:
    return ensure_clip(point.config, cache_dir() / SWEEP_SUITE / f"point_{number:02d}")


def _truth(files: ClipFiles) -> tuple[MaskTrack | None, list[int]]:
    """The clip's true masks and the scored frames where the animal shows; none where the
    generator's rule (``core.synth.compose.VISIBLE_CONTRAST``) saw it in no frame."""
    clip = open_clip(files.video)
    try:
        truth = read_masks(files.masks_dir, clip)
    except InputError:     # every mask empty: not visible
        return None, []
    return truth, [t for t in range(0, clip.num_frames, STRIDE) if truth.mask(t).any()]


def _contrast_levels(files: ClipFiles) -> float:
    """The mean |grey inside − grey outside| along the true outline over the scored frames,
    in grey levels (module doc)."""
    truth, scored = _truth(files)
    kernel = np.ones((3, 3), np.uint8)
    differences = []
    with VideoReader(open_clip(files.video)) as frames:
        for t in scored:
            grey = cv2.cvtColor(frames[t], cv2.COLOR_RGB2GRAY).astype(np.float32)
            mask = truth.mask(t).astype(np.uint8)
            inside = (cv2.erode(mask, kernel, iterations=RING_PX[0]).astype(bool)
                      & ~cv2.erode(mask, kernel, iterations=RING_PX[1]).astype(bool))
            outside = (cv2.dilate(mask, kernel, iterations=RING_PX[1] + 1).astype(bool)
                       & ~cv2.dilate(mask, kernel, iterations=RING_PX[0] + 1).astype(bool))
            differences.append(abs(float(grey[inside].mean()) - float(grey[outside].mean())))
    return float(np.mean(differences))


def _width(files: ClipFiles) -> dict:
    """The animal's width at its widest in the true masks, px (their median)."""
    truth, scored = _truth(files)
    return {"width_px": float(np.median([widest_px(truth.mask(t)) for t in scored]))}


def _scores(files: ClipFiles, config: SynthConfig, backend: str) -> dict:
    """One back-end's masks on one point's clip against the truth (module doc)."""
    truth, scored = _truth(files)
    clip = open_clip(files.video)
    segmenter = make_segmenter(backend, only_frames=scored)
    with VideoReader(clip) as frames:
        track, _timed, error = timed_pass(segmenter, frames, click_seed(files))
    altitude = load_telemetry(clip, files.altitude_csv).altitude_m
    focal_px = synth_camera(config).intrinsics(clip).focal_px
    truth_m3 = float(read_json(files.truth_json, "the truth")["volume_m3"])
    offsets, ious, volumes = [], [], []
    for t in scored:
        true = truth.mask(t)
        ours = track.mask(t) if track is not None else np.zeros_like(true)
        offsets.append(outline_offset_px(ours, true))
        ious.append(mask_iou(ours, true))
        on_ours = elliptical_error(ours, float(altitude[t]), focal_px, truth_m3)
        on_truth = elliptical_error(true, float(altitude[t]), focal_px, truth_m3)
        volumes.append((1 + on_ours) / (1 + on_truth) - 1)
    return {"outline_offset_px": float(np.mean(offsets)), "mean_iou": float(np.mean(ious)),
            # elliptical, against the true masks; NaN where no mask gave a midline
            "volume_error": (float(np.nanmean(volumes)) if np.isfinite(volumes).any()
                             else float("nan")),
            "error": error}
