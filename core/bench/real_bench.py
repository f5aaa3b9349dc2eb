"""``dolphinfit bench real``: the product against people, on real drone images.

Four parts, each on data in ``core.bench.real_data``:

1. **MedidoR replay**: the clicks of MedidoR's GUI test through our annotation geometry
   (``annotation.MEDIDOR``: straight segments, widths between the two clicks) against the
   spreadsheet MedidoR wrote from them, and through our own geometry (spline, perpendicular
   widths) to show how much the two conventions differ.
2. **Minke**: our masks (default back-end, from a click on the back and from the automatic
   seed) give a suggested length and 19 widths (``mask_midline.annotation_from_mask``, as
   "suggest edges" places them); against each of the two people who measured the image, and
   the two people against each other: the spread we must fall inside.
3. **Right whale**: the same masks against MedidoR's test clicks (not an expert's): length and
   widths, and the signed offset of our outline from each clicked edge point along the line
   through the pair (+: our outline lies outside), in pixels and as a share of the width.
   Foam along both flanks and the calf beside the mother are part of the test.
4. **Outlines**: on 639 real whale outlines (rostrum to peduncle), our midline from the mask
   and our perpendicular widths against the hand points: the midline's ends against the
   rostrum and peduncle points, and at each hand-placed pair across the body, our width at
   that station against the person's (the straight distance between their points), beside
   the outline's own width along the person's line (how far the outline and the hand points
   disagree in the data itself).
5. **Fit** (``core.bench.real_fit``): the 3D fit on the minke still against the two people,
   with its 95 % intervals.
"""

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.bench.real_fit import fit_minke
from dolphinfit.core.bench.real_overlay import overlay, write_overlay
from dolphinfit.core.bench.real_data import (
    OUTLINE_PAIRS, HumanMeasurement, MedidorImage, MinkeImage, WhaleOutlines, load_medidor,
    load_minke, load_outlines,
)
from dolphinfit.core.errors import InputError
from dolphinfit.core.measure.annotation import (
    MEDIDOR, Annotation, Stations, pixel_measurements, place_stations, suggest_edges,
)
from dolphinfit.core.measure.mask_midline import annotation_from_mask, midline_from_mask
from dolphinfit.core.measure.stations import NUM_STATIONS, STATION_PCT
from dolphinfit.core.segment.backends import DEFAULT_BACKEND, make_segmenter
from dolphinfit.core.segment.segmenter import AutoSeed, PointSeed, Seed

SEEDS = ("click", "auto")
OUTLINE_PAD_PX = 8       # water around a rasterised outline
SUPERSAMPLE = 4         # outlines are filled at this many × the pixel grid
CHORD_REACH = 2.0        # an edge is looked for this many × the clicked width from its centre


@dataclass(frozen=True)
class ReplayScore:
    """MedidoR's spreadsheet against its clicks replayed through our geometry (pixels)."""

    sheet_length_px: float
    length_px: float             # MEDIDOR geometry
    default_length_px: float     # our spline geometry
    sheet_widths_px: list[float]   # 10 … 90 %
    widths_px: list[float]
    default_widths_px: list[float]
    max_abs_difference_px: float          # MEDIDOR geometry against the sheet, all values
    default_max_abs_difference_px: float  # our geometry against the sheet


@dataclass(frozen=True)
class MaskMeasure:
    """Length and widths suggested from our mask of a still from one kind of seed."""

    seed: str
    length_m: float
    widths_m: list[float]        # the 19 stations, NaN where no edge was found
    seconds: float
    error: str = ""              # why no mask came out


def load_rgb(path: Path) -> np.ndarray:
    """(H, W, 3) uint8 RGB of an image file."""
    image = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if image is None:
        raise InputError(f"{path}: cannot be read as an image")
    return cv2.cvtColor(image, cv2.COLOR_BGR2RGB)


def replay_medidor(data: MedidorImage) -> ReplayScore:
    """MedidoR's test clicks through both geometries against its spreadsheet."""
    stations = np.arange(1, 10) * 2 - 1   # 10, 20, … 90 % on the 5 % grid
    edges = np.full((NUM_STATIONS, 2, 2), np.nan)
    edges[stations] = data.width_clicks_px[:, ::-1]   # first click is side B (above)
    annotation = Annotation(0, data.length_clicks_px, edges)
    ours, default = pixel_measurements(annotation, MEDIDOR), pixel_measurements(annotation)
    sheet = [data.sheet.widths_px[pct] for pct in STATION_PCT[stations]]

    def worst(measured) -> float:
        return float(np.max(np.abs(np.r_[measured.length_px - data.sheet.length_px,
                                          measured.widths_px[stations] - sheet])))

    return ReplayScore(data.sheet.length_px, ours.length_px, default.length_px, sheet,
                       ours.widths_px[stations].tolist(), default.widths_px[stations].tolist(),
                       worst(ours), worst(default))


def seed_of(kind: str, click_px: tuple[float, float]) -> Seed:
    """The seed a user gives: a click on the animal, or none (the automatic seed)."""
    return PointSeed(*click_px) if kind == "click" else AutoSeed()


def still_mask(rgb: np.ndarray, seed: Seed, backend: str = DEFAULT_BACKEND) -> np.ndarray:
    """(H, W) bool mask of the animal in a still from ``seed``; InputError if none."""
    return make_segmenter(backend).segment([rgb], seed).mask(0)


def measure_still(rgb: np.ndarray, kind: str, click_px: tuple[float, float],
                  m_per_px: float, backend: str = DEFAULT_BACKEND
                  ) -> tuple[MaskMeasure, np.ndarray | None, Annotation | None]:
    """Our mask of a still from one kind of seed, the length and widths it suggests (metres),
    the mask and the suggested annotation (None where no animal was found)."""
    start = time.perf_counter()
    try:
        mask = still_mask(rgb, seed_of(kind, click_px), backend)
        annotation = annotation_from_mask(mask)
    except (InputError, ValueError) as exc:
        return (MaskMeasure(kind, float("nan"), [float("nan")] * NUM_STATIONS,
                            time.perf_counter() - start, str(exc)), None, None)
    pixels = pixel_measurements(annotation)
    return (MaskMeasure(kind, pixels.length_px * m_per_px,
                        (pixels.widths_px * m_per_px).tolist(), time.perf_counter() - start),
            mask, annotation)


def human_spread(humans: tuple[HumanMeasurement, ...]) -> dict:
    """The people against each other: length and the widths at the stations all measured,
    in metres and as shares of their mean."""
    people = np.array([h.station_widths() for h in humans])
    shared = np.all(np.isfinite(people), axis=0)
    mean, spread = people.mean(axis=0)[shared], np.ptp(people, axis=0)[shared]
    lengths = np.array([h.length_m for h in humans])
    return {"stations_pct": STATION_PCT[shared].tolist(),
            "length_m": float(np.ptp(lengths)),
            "length_share": float(np.ptp(lengths) / lengths.mean()),
            "widths_m": spread.tolist(),
            "median_width_share": float(np.median(spread / mean)),
            "worst_width_share": float(np.max(spread / mean))}


def against_humans(measure: MaskMeasure, humans: tuple[HumanMeasurement, ...]) -> dict:
    """Our length and widths against the people's mean, at the stations all measured, in
    metres and as shares; how many widths lie within half the people's spread of their
    mean (inside the range the two people span)."""
    people = np.array([h.station_widths() for h in humans])
    shared = np.all(np.isfinite(people), axis=0)
    mean, spread = people.mean(axis=0)[shared], np.ptp(people, axis=0)[shared]
    error = np.asarray(measure.widths_m)[shared] - mean
    length = np.mean([h.length_m for h in humans])
    share = np.abs(error) / mean
    return {"length_error_m": measure.length_m - length,
            "length_error_share": measure.length_m / length - 1,
            "width_error_m": error.tolist(),
            "median_width_error_share": float(np.nanmedian(share)),
            "worst_width_error_share": float(np.nanmax(share)) if np.isfinite(share).any()
            else float("nan"),
            "widths_within_spread": int(np.sum(np.abs(error) <= spread / 2))}


def chord_stations(first_px: np.ndarray, second_px: np.ndarray) -> Stations:
    """Stations at the middles of point pairs (N, 2) whose "perpendiculars" run along each
    pair (side A towards ``second_px``): a mask's edges along a person's own line."""
    direction = second_px - first_px
    chord = np.linalg.norm(direction, axis=1)
    return Stations(length_px=float(2 * CHORD_REACH * chord.max()),
                    fractions=np.zeros(len(chord)), points_px=(first_px + second_px) / 2,
                    normals=direction / chord[:, None])


def edge_point_offsets(mask: np.ndarray, first_px: np.ndarray,
                       second_px: np.ndarray) -> np.ndarray:
    """(N, 2) signed offset (px) of the mask's outline from each person's edge point (second,
    first) along the line through the pair, + where the outline lies outside; NaN where the
    line does not leave the mask."""
    stations = chord_stations(first_px, second_px)
    found = suggest_edges(mask, stations)
    reach = np.linalg.norm(found - stations.points_px[:, None, :], axis=2)
    half = np.linalg.norm(second_px - first_px, axis=1)[:, None] / 2
    return reach - half


def right_whale_offsets(mask: np.ndarray, data: MedidorImage) -> dict:
    """Our outline against the clicked edge points (10 … 90 %): signed offsets in px and as a
    share of the clicked width."""
    first, second = data.width_clicks_px[:, 0], data.width_clicks_px[:, 1]
    offsets = edge_point_offsets(mask, first, second)
    widths = np.linalg.norm(second - first, axis=1)
    return {"stations_pct": list(range(10, 100, 10)), "offset_px": offsets.tolist(),
            "offset_share": (offsets / widths[:, None]).tolist(),
            "offsets_found": int(np.isfinite(offsets).sum()),
            **_signed_summary(offsets)}


def _signed_summary(offsets: np.ndarray) -> dict:
    """Median, median |offset| and the largest offset (signed) of the finite ones; NaN if
    none."""
    finite = offsets[np.isfinite(offsets)]
    if not finite.size:
        return {"median_offset_px": float("nan"), "median_abs_offset_px": float("nan"),
                "worst_offset_px": float("nan")}
    return {"median_offset_px": float(np.median(finite)),
            "median_abs_offset_px": float(np.median(np.abs(finite))),
            "worst_offset_px": float(finite[np.argmax(np.abs(finite))])}


def rasterised(outline: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(coverage, origin): the share of each pixel an outline (2, P) covers, (H, W) float32
    over its bounding box with ``OUTLINE_PAD_PX`` around (filled at ``SUPERSAMPLE``× and
    averaged, so that its 0.5 level lies on the outline within a tenth of a pixel); origin
    (x, y) of pixel (0, 0) in the image."""
    origin = np.floor(outline.min(axis=1)) - OUTLINE_PAD_PX
    size = np.ceil(outline.max(axis=1) - origin).astype(int) + OUTLINE_PAD_PX + 1
    fine = np.zeros((size[1] * SUPERSAMPLE, size[0] * SUPERSAMPLE), np.uint8)
    # fine pixel centres sit at (k + 0.5) / SUPERSAMPLE − 0.5 in pixels of the image
    corners = (outline.T - origin + 0.5) * SUPERSAMPLE - 0.5
    cv2.fillPoly(fine, [np.round(corners * 4).astype(np.int32)], 255, shift=2)
    coverage = cv2.resize(fine, tuple(size), interpolation=cv2.INTER_AREA)
    return coverage.astype(np.float32) / 255.0, origin


def arc_fraction(midline_px: np.ndarray, points_px: np.ndarray) -> np.ndarray:
    """(N,) the arc-length fraction along the midline spline nearest to each point."""
    dense = place_stations(midline_px, np.linspace(0.0, 1.0, 2001))
    gaps = np.linalg.norm(dense.points_px[None, :, :] - points_px[:, None, :], axis=2)
    return dense.fractions[np.argmin(gaps, axis=1)]


def score_outline(outline: np.ndarray, points: dict[str, np.ndarray]) -> dict:
    """One whale: our midline's ends and widths against its hand points (px)."""
    mask, origin = rasterised(outline)
    local = {name: p - origin for name, p in points.items()}
    midline = midline_from_mask(mask, head_near=local["rostrum"])
    first = np.array([local[f"side1_{pair}"] for pair in OUTLINE_PAIRS])
    second = np.array([local[f"side2_{pair}"] for pair in OUTLINE_PAIRS])
    fractions = np.clip(arc_fraction(midline, (first + second) / 2), 0.005, 0.995)
    ours = suggest_edges(mask, place_stations(midline, fractions))
    along_chord = suggest_edges(mask, chord_stations(first, second))
    return {"rostrum_px": float(_beyond(midline[0], midline[1], local["rostrum"])),
            "peduncle_px": float(_beyond(midline[-1], midline[-2], local["peduncle"])),
            "human_px": np.linalg.norm(second - first, axis=1),
            "ours_px": np.linalg.norm(ours[:, 0] - ours[:, 1], axis=1),
            "outline_px": np.linalg.norm(along_chord[:, 0] - along_chord[:, 1], axis=1)}


def _beyond(end: np.ndarray, inner: np.ndarray, point: np.ndarray) -> float:
    """How far the midline's ``end`` lies beyond a person's ``point`` along the midline's
    end direction (from ``inner``), px; + where the midline runs further: what the length
    follows."""
    direction = (end - inner) / np.linalg.norm(end - inner)
    return float((end - point) @ direction)


def _abs_summary(differences: np.ndarray, widths: np.ndarray) -> dict:
    finite = np.isfinite(differences)
    size = np.abs(differences[finite])
    share = size / widths[finite]
    return {"median_px": float(np.median(size)), "worst_px": float(np.max(size)),
            "median_share": float(np.median(share)), "worst_share": float(np.max(share)),
            "missing": int(np.sum(~finite))}


def outline_scores(data: WhaleOutlines, limit: int | None = None) -> dict:
    """Our midline and widths on every usable outline (the first ``limit``), summarised per
    hand-placed pair: median and worst |difference| in px and as a share of the person's
    width, for ours − person, outline − person and ours − outline."""
    skipped = {index for index, _ in data.left_out}
    chosen = [i for i in range(len(data.outlines)) if i not in skipped][:limit]
    scores = [score_outline(data.outlines[i], {k: v[i] for k, v in data.points.items()})
              for i in chosen]
    human = np.array([s["human_px"] for s in scores])
    ours = np.array([s["ours_px"] for s in scores])
    outline = np.array([s["outline_px"] for s in scores])
    pairs = {pair: {"ours_vs_human": _abs_summary(ours[:, k] - human[:, k], human[:, k]),
                    "outline_vs_human": _abs_summary(outline[:, k] - human[:, k], human[:, k]),
                    "ours_vs_outline": _abs_summary(ours[:, k] - outline[:, k], human[:, k])}
             for k, pair in enumerate(OUTLINE_PAIRS)}
    ends = {name: _signed_summary(np.array([s[f"{name}_px"] for s in scores]))
            for name in ("rostrum", "peduncle")}
    return {"outlines": len(scores), "left_out": [list(item) for item in data.left_out],
            "ends": ends, "pairs": pairs}


PARTS = ("replay", "minke", "right-whale", "outlines", "fit")


def bench_real(folder: Path | None = None, parts: tuple[str, ...] = PARTS,
               seeds: tuple[str, ...] = SEEDS, backend: str = DEFAULT_BACKEND,
               outlines_limit: int | None = None,
               progress: Callable[[str], None] | None = None,
               overlays: Path | None = None) -> dict:
    """The chosen ``parts`` of the module doc (1–5), as one JSON-ready dict; with
    ``overlays``, a picture per image and seed there (``real_overlay``)."""
    def say(line: str) -> None:
        if progress is not None:
            progress(line)

    figures: dict = {}
    if "replay" in parts:
        figures["medidor_replay"] = asdict(replay_medidor(load_medidor(folder)))
        say("MedidoR replay done")
    if "minke" in parts:
        figures["minke"] = minke_figures(load_minke(folder), seeds, backend, say, overlays)
    if "right-whale" in parts:
        figures["right_whale"] = right_whale_figures(load_medidor(folder), seeds, backend, say,
                                                     overlays)
    if "outlines" in parts:
        figures["outlines"] = outline_scores(load_outlines(folder), outlines_limit)
        say("outlines done")
    if "fit" in parts:
        figures["minke_fit"] = fit_minke(load_minke(folder), backend)
        say("minke fit done")
    return figures


def minke_figures(minke: MinkeImage, seeds: tuple[str, ...], backend: str,
                  say: Callable[[str], None], overlays: Path | None = None) -> dict:
    """Part 2: the people's spread and our masks' measurements against them."""
    rgb = load_rgb(minke.image)
    figures: dict = {"humans": [asdict(h) for h in minke.humans],
                     "human_spread": human_spread(minke.humans), "seeds": {}}
    for kind in seeds:
        measure, mask, annotation = measure_still(rgb, kind, minke.click_px,
                                                  minke.calibration.m_per_px, backend)
        if overlays is not None and mask is not None:
            write_overlay(overlays / f"minke_{kind}.png", overlay(
                rgb, mask, annotation, click_px=minke.click_px if kind == "click" else None))
        figures["seeds"][kind] = {**asdict(measure), **against_humans(measure, minke.humans)}
        say(f"minke from the {kind}: {measure.error or 'measured'}")
    return figures


def right_whale_figures(medidor: MedidorImage, seeds: tuple[str, ...], backend: str,
                        say: Callable[[str], None], overlays: Path | None = None) -> dict:
    """Part 3: our masks' length and outline against MedidoR's test clicks."""
    rgb = load_rgb(medidor.image)
    figures: dict = {"sheet_length_px": medidor.sheet.length_px, "seeds": {}}
    for kind in seeds:
        measure, mask, annotation = measure_still(rgb, kind, medidor.click_px,
                                                  medidor.calibration.m_per_px, backend)
        entry = asdict(measure)
        if mask is not None:
            entry["length_px"] = pixel_measurements(annotation).length_px
            entry.update(right_whale_offsets(mask, medidor))
            if overlays is not None:
                clicks = np.concatenate([medidor.length_clicks_px,
                                         medidor.width_clicks_px.reshape(-1, 2)])
                write_overlay(overlays / f"right_whale_{kind}.png", overlay(
                    rgb, mask, annotation, clicks,
                    medidor.click_px if kind == "click" else None))
        figures["seeds"][kind] = entry
        say(f"right whale from the {kind}: {measure.error or 'measured'}")
    return figures
