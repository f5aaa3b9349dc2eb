"""``dolphinfit bench masks``: each mask back-end against the truth on the widened suite.

Every back-end starts from the same click: the truth's ``seed_px`` (a point inside the target)
in the first frame where the target is visible, as a user would click the animal to measure,
with a second animal beside it in some clips. It segments the frames a suite fit uses (every
``stride``-th frame; the colour tracker, being cheap, runs on all of them as the app does) and
is scored on those frames:

- **IoU** of the whole mask (a frame where both the truth and the result are empty scores 1,
  one where only one is empty 0);
- **flukes** and **rostrum IoU**: the same within a zone around that part's true region
  (``parts.npz``; the zone is the region grown by ``PART_ZONE_PX``), over the frames where the
  part is visible: the parts that decide the body length;
- **outline offset**: how far the outline lies outside (+) or inside (−) the true one, in
  pixels, averaged over the scored frames (``evaluate.outline_offset_px``): the figure volume
  follows, where IoU does not say in which direction a mask errs;
- **seconds per segmented frame**, wall time of the whole pass (for SAM-2 including
  building its model from the checkpoint, once per clip); and the same pass apart: the
  **seed's** seconds (from the start to the first frame's mask: finding the animal, once per
  clip) and the seconds per frame **tracked** after it (what a longer clip costs a frame).

The same scores from the other ways a user starts (``SEED_KINDS``): the automatic seed as
``dolphinfit fit`` makes it (the animal a scan of the clip follows longest, else a search
from the click's frame sized by the clip's camera and altitudes; the scan's own seconds are
left out: ``bench scan`` and ``bench e2e`` time it), and a box: the bounding box of the true
mask in the click's frame, as a user would draw it.
"""

import time
from dataclasses import asdict, dataclass, field
from functools import cache
from pathlib import Path

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.bench.scenario import synth_camera
from dolphinfit.core.fit.config import FitConfig
from dolphinfit.core.fit.pipeline import scanned_seed, sized_auto_seed
from dolphinfit.core.io.json_file import read_json
from dolphinfit.core.io.masks import MaskTrack, read_png_folder
from dolphinfit.core.io.telemetry import load_telemetry
from dolphinfit.core.io.video import Clip, VideoReader, open_clip
from dolphinfit.core.iou import mask_iou
from dolphinfit.core.limits import one_of
from dolphinfit.core.segment.backends import ALWAYS_AVAILABLE, COLOUR, make_segmenter
from dolphinfit.core.segment.evaluate import box_seed_from, outline_offset_px
from dolphinfit.core.segment.seed import dilate
from dolphinfit.core.segment.segmenter import Frames, PointSeed, Seed, Segmenter
from dolphinfit.core.synth.config import SynthConfig
from dolphinfit.core.synth.files import ClipFiles, read_part_masks

PART_ZONE_PX = 4
DEFAULT_STRIDE = 4    # the suite's clips are 10 fps and fitted at 2.5 fps
CLICK, AUTO, BOX = "click", "auto", "box"
SEED_KINDS = (CLICK, AUTO, BOX)


@dataclass(frozen=True)
class SeedScore:
    """One back-end on one clip from one kind of seed."""

    mean_iou: float
    min_iou: float
    flukes_iou: float     # NaN when the flukes are never visible in the scored frames
    rostrum_iou: float
    seconds_per_frame: float
    outline_offset_px: float = float("nan")   # mean over the frames where the target shows
    error: str = ""       # why the back-end gave no masks at all (scored as empty masks)
    seed_seconds: float = float("nan")                # to the first frame's mask
    seconds_per_tracked_frame: float = float("nan")   # each frame after it


@dataclass(frozen=True)
class PassTime:
    """How long one segmenting pass took: in all, to its first frame's mask (the seed: the
    back-ends report each frame as it is done, the seed's first) and after it."""

    seconds: float
    seed_seconds: float = float("nan")   # NaN: no frame reported

    @property
    def after_seed_seconds(self) -> float:
        return self.seconds - self.seed_seconds


@dataclass(frozen=True)
class MaskScore:
    """One back-end on one clip: from the click (the first fields) and, in ``seeds``, from
    the other kinds of seed."""

    clip: str
    backend: str
    mean_iou: float
    min_iou: float
    flukes_iou: float     # NaN when the flukes are never visible in the scored frames
    rostrum_iou: float
    frames: int           # frames scored
    seconds_per_frame: float
    outline_offset_px: float = float("nan")
    error: str = ""       # why the back-end gave no masks at all (scored as empty masks)
    seeds: dict[str, SeedScore] = field(default_factory=dict)
    seed_seconds: float = float("nan")
    seconds_per_tracked_frame: float = float("nan")


def target_clicks(truth: dict) -> list[PointSeed]:
    """A click on the target (truth's ``seed_px``) in each frame where it is visible."""
    return [PointSeed(float(frame["seed_px"][0]), float(frame["seed_px"][1]), int(frame["frame"]))
            for frame in truth["frames"]
            if frame.get("visible") and frame.get("seed_px") is not None]


def click_seed(files: ClipFiles) -> PointSeed:
    """The click on the target in its first visible frame."""
    clicks = target_clicks(read_json(files.truth_json, "the clip's truth"))
    if not clicks:
        raise ValueError(f"{files.truth_json}: the target is never visible")
    return clicks[0]


@cache
def auto_seed(files: ClipFiles, clip: Clip, frame_idx: int) -> Seed:
    """The automatic seed as ``dolphinfit fit`` makes it (module doc), ``frame_idx`` the
    frame its fallback searches from; made once per clip for all back-ends."""
    config = SynthConfig.from_json(read_json(files.truth_json, "the clip's truth")["config"])
    intrinsics = synth_camera(config).intrinsics(clip)
    telemetry = load_telemetry(clip, files.srt)
    with VideoReader(clip) as frames:
        seed, _line = scanned_seed(frames, telemetry, intrinsics, FitConfig(),
                                   sized_auto_seed(frame_idx, intrinsics, telemetry), None, None)
    return seed


def seeds_of(kinds: tuple[str, ...], files: ClipFiles, clip: Clip, click: PointSeed,
             truth: MaskTrack) -> dict[str, Seed]:
    """The click and each kind's seed (``SEED_KINDS``; module doc)."""
    made = {CLICK: lambda: click, AUTO: lambda: auto_seed(files, clip, click.frame_idx),
            BOX: lambda: box_seed_from(truth, click.frame_idx)}
    return {kind: made[kind]() for kind in dict.fromkeys((CLICK, *kinds))}


def part_iou(result: np.ndarray, truth: np.ndarray, region: np.ndarray) -> float:
    """IoU of the two masks within the zone around one part's true region."""
    zone = dilate(region, PART_ZONE_PX)
    return mask_iou(result & zone, truth & zone)


def score_backend(name: str, files: ClipFiles, backend: str, stride: int = DEFAULT_STRIDE,
                  seeds: tuple[str, ...] = (CLICK,),
                  checkpoint: Path | None = None) -> MaskScore:
    """Segment one clip with one back-end from each kind of seed in ``seeds`` (the click
    always) and score it (module doc); ``checkpoint``: SAM-2's, for the sam2 back-end."""
    clip = open_clip(files.video)
    truth = read_png_folder(files.masks_dir, clip)
    parts = read_part_masks(files.parts)
    click = click_seed(files)
    scored = sorted(set(range(click.frame_idx % stride, clip.num_frames, stride)))
    segmented = clip.num_frames if backend == COLOUR else len(scored)
    by_kind = {}
    segmenter = make_segmenter(backend, only_frames=scored, checkpoint=checkpoint)
    for kind, seed in seeds_of(seeds, files, clip, click, truth).items():
        with VideoReader(clip) as frames:   # no masks: every frame scores as empty
            track, timed, error = timed_pass(segmenter, frames, seed)
        by_kind[kind] = _scores(track, truth, parts, scored, timed, segmented, error)
    first = by_kind.pop(CLICK)
    return MaskScore(clip=name, backend=backend, mean_iou=first.mean_iou,
                     min_iou=first.min_iou, flukes_iou=first.flukes_iou,
                     rostrum_iou=first.rostrum_iou, frames=len(scored),
                     seconds_per_frame=first.seconds_per_frame,
                     outline_offset_px=first.outline_offset_px, error=first.error,
                     seeds=by_kind, seed_seconds=first.seed_seconds,
                     seconds_per_tracked_frame=first.seconds_per_tracked_frame)


def timed_pass(segmenter: Segmenter, frames: Frames,
               seed: Seed) -> tuple[MaskTrack | None, PassTime, str]:
    """``segmenter.segment(frames, seed)``, how long it took (``PassTime``) and why it gave
    no masks ("" when it did; None and the InputError's message where the seed found
    nothing)."""
    reported = []
    start = time.perf_counter()
    try:
        track, error = segmenter.segment(
            frames, seed, progress=lambda _report: reported.append(time.perf_counter())), ""
    except InputError as exc:
        track, error = None, str(exc)
    seed_seconds = reported[0] - start if reported else float("nan")
    return track, PassTime(time.perf_counter() - start, seed_seconds), error


def _scores(track: MaskTrack | None, truth: MaskTrack, parts: dict[str, np.ndarray],
            scored: list[int], timed: PassTime, segmented: int, error: str) -> SeedScore:
    """The IoUs of ``track`` (None: no masks) on the scored frames; the pass's time per
    frame of the ``segmented``, and apart (``PassTime``)."""
    ious, offsets, part_ious = [], [], {part: [] for part in ("flukes", "rostrum")}
    for t in scored:
        target = truth.mask(t)
        result = track.mask(t) if track is not None else np.zeros_like(target)
        ious.append(mask_iou(result, target))
        if target.any():
            offsets.append(outline_offset_px(result, target))
        for part, values in part_ious.items():
            region = parts[part][t] & target
            if region.any():
                values.append(part_iou(result, target, region))
    part_means = {part: float(np.mean(values)) if values else float("nan")
                  for part, values in part_ious.items()}
    return SeedScore(mean_iou=float(np.mean(ious)), min_iou=float(np.min(ious)),
                     flukes_iou=part_means["flukes"], rostrum_iou=part_means["rostrum"],
                     seconds_per_frame=timed.seconds / segmented,
                     outline_offset_px=float(np.mean(offsets)) if offsets else float("nan"),
                     error=error, seed_seconds=timed.seed_seconds,
                     seconds_per_tracked_frame=(timed.after_seed_seconds / (segmented - 1)
                                                if segmented > 1 else float("nan")))


def _means(scores: list[SeedScore | MaskScore]) -> dict[str, float]:
    """The mean over clips of each figure, the worst clip's mean IoU, and the mean and worst
    size of the clips' outline offsets."""
    offsets = np.abs([s.outline_offset_px for s in scores])
    return {"mean_iou": float(np.mean([s.mean_iou for s in scores])),
            "mean_abs_outline_offset_px": float(np.nanmean(offsets)),
            "worst_outline_offset_px": float(np.nanmax(offsets)),
            "worst_clip_iou": float(np.min([s.mean_iou for s in scores])),
            "flukes_iou": float(np.nanmean([s.flukes_iou for s in scores])),
            "rostrum_iou": float(np.nanmean([s.rostrum_iou for s in scores])),
            "seconds_per_frame": float(np.mean([s.seconds_per_frame for s in scores])),
            "seed_seconds": _known_mean([s.seed_seconds for s in scores]),
            "seconds_per_tracked_frame": _known_mean([s.seconds_per_tracked_frame
                                                      for s in scores])}


def _known_mean(values: list[float]) -> float:
    """The mean of the values that are not NaN (a pass that found no animal has no seed
    time); NaN when none is."""
    known = [value for value in values if not np.isnan(value)]
    return float(np.mean(known)) if known else float("nan")


def summarize(scores: list[MaskScore]) -> dict[str, dict]:
    """Per back-end: ``_means`` from the click, and in ``seeds`` those of the other seeds."""
    summary = {}
    for backend in dict.fromkeys(s.backend for s in scores):
        chosen = [s for s in scores if s.backend == backend]
        kinds = dict.fromkeys(kind for s in chosen for kind in s.seeds)
        summary[backend] = {**_means(chosen),
                            "seeds": {kind: _means([s.seeds[kind] for s in chosen])
                                      for kind in kinds}}
    return summary


def bench_masks(clips: dict[str, ClipFiles], backends: tuple[str, ...] = ALWAYS_AVAILABLE,
                stride: int = DEFAULT_STRIDE, seeds: tuple[str, ...] = SEED_KINDS,
                progress=None, checkpoint: Path | None = None) -> dict:
    """Every back-end on every clip from each kind of seed in ``seeds`` (the click always),
    side by side; ``progress(score)`` after each; ``checkpoint``: SAM-2's, when
    ``backends`` include sam2."""
    for kind in seeds:
        one_of(kind, SEED_KINDS, "seed kind")
    scores = []
    for name, files in clips.items():
        for backend in backends:
            scores.append(score_backend(name, files, backend, stride, seeds, checkpoint))
            if progress is not None:
                progress(scores[-1])
    return {"clips": [asdict(s) for s in scores], "summary": summarize(scores),
            "stride": stride, "part_zone_px": PART_ZONE_PX, "seed_kinds": list(seeds)}
