"""The outline where the image puts it: the body's edge found to a fraction of a pixel by
fitting the image's step across it, whatever drew the mask.

A body of level a over water of level b, blurred by the optics (a Gaussian of σ) and
integrated over each pixel, shows across its edge the profile

    I(s) = b + (a − b) Φ(s / σₑ),   σₑ² = σ² + 1/12

with s the signed distance of a pixel's centre from the edge (inside positive) and 1/12 the
variance of a pixel's footprint across any line. The edge is where the profile is half-way
between the levels, at any blur and any contrast; a pixel is the animal's when at least half of
it is covered, that is (for an edge straight across the pixel) when its centre lies inside.

A convex edge of curvature κ is half-way a little inside, where the blurred level is
½ − κσₑ φ(0)/2 (the Gaussian's mass beyond a parabola); the mask's pixels are decided
against that level.

1. **Grey levels**: each pixel's colour projected on the direction that best tells the body's
   colours from the water's (Fisher's, from a ring just inside and one just outside the mask),
   scaled so that the water reads 0 and the body 1.
2. **Reference outline**: the half-level line of the mask lightly smoothed (sub-pixel, no
   staircase); every pixel within ``band_px`` (plus ``max_shift_px``) of it gets its signed
   distance to it, the segment of the outline it is nearest to (segments ``segment_px``
   long) and the outline's curvature there.
3. **Fit**: per segment, the profile above with the segment's own levels (the body's flank and
   the water beside it differ along the animal) at every shift of the edge on a grid, levels by
   weighted least squares. σₑ is the window's: the one of ``sigma_grid_px`` whose steps leave
   the least unexplained on a coarse grid of shifts; each shift is then refined on a fine
   grid, down-weighting what does not follow a step (glitter, foam, a companion) in
   ``robust_rounds``.
4. **Trust**: a segment's shift counts where its step is clear (contrast, fit, pixels on both
   sides, a minimum inside the search); the shifts and levels are smoothed along the outline
   and filled in from the neighbours where a segment gave none. Where less than
   ``min_edge_share`` of the segments showed a step (a whale a metre down fades into the
   water over many pixels), the mask stays as drawn: the image does not say where its edge is.
5. **Mask**: each pixel near the outline is the animal's where it is at least half the body's
   (above): its own level between the local water's and body's, averaged with what the
   shifted outline predicts there by their certainties (the image's noise against the
   reference outline's error at a pixel); where its segment showed no step, the shifted
   outline alone decides.
6. **Again**: a second pass from the new mask at the blur found, so that the fit's pixels lie
   evenly about the edge (the tuning split's true masks grown by 0.86 px ended 0.16 px out
   after one pass, 0.12 px after two, on average over its clips).
"""

from dataclasses import dataclass, replace

import contourpy
import cv2
import numpy as np
from scipy.ndimage import gaussian_filter1d
from scipy.sparse import csr_matrix
from scipy.spatial import cKDTree
from scipy.special import ndtr

from dolphinfit.core.segment.evaluate import outline_offset_px

PIXEL_VARIANCE = 1.0 / 12.0          # a pixel's footprint across a line (module doc)
HALF_LEVEL_PER_BEND = 1.0 / (2.0 * np.sqrt(2.0 * np.pi))   # φ(0)/2 (module doc)


@dataclass(frozen=True)
class OutlineFitSettings:
    """How the outline is fitted (module doc)."""

    band_px: float = 4.0              # pixels this far from the outline take part
    segment_px: float = 5.0           # length of outline each shift is fitted over
    max_shift_px: float = 2.0         # the edge is looked for this far either side
    coarse_step_px: float = 0.25      # the blur is chosen on this grid of shifts
    shift_step_px: float = 0.05       # then each shift refined on this one
    sigma_grid_px: tuple[float, ...] = (0.4, 0.55, 0.75, 1.0, 1.35, 1.8, 2.5)
    reference_smoothing_px: float = 0.8
    reference_error_px: float = 0.15  # the reference outline's error at a pixel (step 5)
    curvature_smoothing_px: float = 1.5
    ring_px: tuple[float, float] = (1.5, 4.5)   # the colour rings' distances from the outline
    min_contrast: float = 0.3         # a segment's step, in units of the window's
    min_explained: float = 0.5        # share of a segment's variance the step explains
    min_side_pixels: int = 3          # pixels a segment needs inside and outside
    min_fitted_share: float = 0.25    # of an outline's segments, for shifts that vary along it
    # of all the segments, for the outline to move at all: a whale a metre down shows a soft
    # edge, 0.4–0.5 of it a step (the minke still), the synthetic splits' animals 0.8–1.0
    min_edge_share: float = 0.7
    smoothing_segments: int = 1       # median over this many segments either side
    robust_rounds: int = 2
    passes: int = 2                   # fits, each from the outline the last one gave
    robust_scale: float = 3.0         # residuals beyond this many robust SDs weigh nothing


@dataclass(frozen=True)
class OutlineFit:
    """The mask with its outline moved where the image puts it, and what the fit saw: how far
    the outline moved outward on average (px; inward negative), the edge's blur σ in pixels
    and the share of the outline that showed an edge (NaN and 0 where none did)."""

    mask: np.ndarray
    moved_px: float
    blur_px: float
    fitted_share: float


@dataclass(frozen=True)
class _Band:
    """The pixels near the outline (module doc, step 2): flat indices, signed distance to the
    reference outline (inside positive), segment, and position along the outline in
    segments."""

    index: np.ndarray
    distance: np.ndarray
    segment: np.ndarray
    position: np.ndarray
    curvature: np.ndarray                   # of the outline where it is nearest, 1/px
    outlines: tuple[tuple[int, int], ...]   # each outline's first segment and count


def refine_outline(image: np.ndarray, mask: np.ndarray,
                   settings: OutlineFitSettings = OutlineFitSettings(),
                   blur_px: float | None = None) -> OutlineFit:
    """The mask (H, W bool) of an animal in ``image`` (H, W, 3 or H, W) with its outline where
    the image puts it (module doc). ``blur_px``: the edge's blur σ where it is known (else
    measured). The mask as drawn where it is empty, the colours do not separate or too little
    of the outline shows a step (``min_edge_share``)."""
    mask = np.asarray(mask, bool)
    fit = _refined_once(image, mask, settings, blur_px)
    if fit.fitted_share < settings.min_edge_share:
        return replace(fit, mask=mask)
    for _pass in range(settings.passes - 1):     # at the blur the first pass found
        fit = _refined_once(image, fit.mask, settings, fit.blur_px)
    return replace(fit, moved_px=outline_offset_px(fit.mask, mask))


def _refined_once(image: np.ndarray, mask: np.ndarray,
                  settings: OutlineFitSettings = OutlineFitSettings(),
                  blur_px: float | None = None) -> OutlineFit:
    """One pass of ``refine_outline`` (module doc, steps 1–5)."""
    unchanged = OutlineFit(mask, 0.0, float("nan"), 0.0)
    if not mask.any() or mask.all():
        return unchanged
    grey = _grey_levels(np.asarray(image, np.float32), mask, settings)
    band = _band(mask, settings)
    if grey is None or band is None:
        return unchanged
    values = grey.ravel()[band.index]
    sigmas = (np.array(settings.sigma_grid_px) if blur_px is None or not np.isfinite(blur_px)
              else np.array([blur_px]))
    coarse = np.arange(-settings.max_shift_px, settings.max_shift_px + 1e-9,
                       settings.coarse_step_px)
    segments = int(band.segment.max()) + 1
    # the blur: the one whose steps, on the coarse grid, leave the least unexplained
    trials = [_segment_fits(band, values, _with_pixel(sigma), np.tile(coarse, (segments, 1)),
                            0, settings) for sigma in sigmas]
    choice = int(np.argmin([trial.score for trial in trials]))
    sigma, first = float(sigmas[choice]), trials[choice]
    fine = np.arange(-settings.coarse_step_px, settings.coarse_step_px + 1e-9,
                     settings.shift_step_px)
    fits = _segment_fits(band, values, _with_pixel(sigma), first.shift[:, None] + fine,
                         settings.robust_rounds, settings)
    # a step found at the ends of the search is no step
    trusted = fits.trusted & (np.abs(first.shift) < settings.max_shift_px - 1e-9)
    fits = replace(fits, trusted=trusted)
    if not trusted.any():
        return unchanged
    decided = _decided_mask(mask, band, values, fits, _with_pixel(sigma), settings)
    return OutlineFit(decided, 0.0, sigma, float(trusted.mean()))


def _with_pixel(sigma_px: float) -> float:
    """σₑ: the optics' blur with a pixel's footprint (module doc)."""
    return float(np.sqrt(sigma_px ** 2 + PIXEL_VARIANCE))


def _grey_levels(image: np.ndarray, mask: np.ndarray,
                 settings: OutlineFitSettings) -> np.ndarray | None:
    """(H, W) float32 levels: 0 the water's colour next to the mask, 1 the body's, along the
    direction that tells them apart best (module doc, step 1); None where they do not."""
    pixels = image.reshape(-1, 1) if image.ndim == 2 else image.reshape(-1, image.shape[2])
    inside = cv2.distanceTransform(mask.astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    outside = cv2.distanceTransform((~mask).astype(np.uint8), cv2.DIST_L2,
                                    cv2.DIST_MASK_PRECISE)
    low, high = settings.ring_px
    body = pixels[((inside >= low) & (inside <= high)).ravel()]
    if len(body) < pixels.shape[1] + 2:       # a thin animal: its whole inside
        body = pixels[(inside >= 1.0).ravel()]
    water = pixels[((outside >= low) & (outside <= high)).ravel()]
    if len(body) < pixels.shape[1] + 2 or len(water) < pixels.shape[1] + 2:
        return None
    difference = np.median(body, 0) - np.median(water, 0)
    spread = (np.cov(body.T).reshape(pixels.shape[1], -1) * len(body)
              + np.cov(water.T).reshape(pixels.shape[1], -1) * len(water)) / (
                  len(body) + len(water))
    spread += np.eye(len(difference)) * max(1e-6, 1e-3 * float(np.trace(spread)))
    direction = np.linalg.solve(spread, difference)
    separation = float(direction @ difference)
    if not separation > 0:
        return None
    direction /= separation
    levels = (pixels - np.median(water, 0)) @ direction
    return levels.reshape(mask.shape).astype(np.float32)


def _band(mask: np.ndarray, settings: OutlineFitSettings) -> _Band | None:
    """The pixels near the mask's reference outline (module doc, step 2)."""
    smooth = cv2.GaussianBlur(mask.astype(np.float32), (0, 0),
                              settings.reference_smoothing_px)
    # closed around a mask cut by the window's side, just beyond it
    lines = [np.asarray(line, float) - 1.0 for line in contourpy.contour_generator(
        z=np.pad(smooth, 1), line_type="Separate").lines(0.5)]
    points, positions, bends, outlines, first = [], [], [], [], 0
    inward = np.stack([cv2.Sobel(smooth, cv2.CV_32F, 1, 0), cv2.Sobel(smooth, cv2.CV_32F, 0, 1)],
                      -1)
    for line in lines:
        dense, arc = _densified(line)
        length = float(arc[-1]) + float(np.hypot(*(dense[0] - dense[-1])))
        if length < settings.segment_px:
            continue
        count = max(1, int(round(length / settings.segment_px)))
        points.append(dense)
        positions.append(first + arc / length * count)
        bends.append(_curvature(dense, inward, settings.curvature_smoothing_px))
        outlines.append((first, count))
        first += count
    if not points:
        return None
    reach = int(np.ceil(settings.band_px + settings.max_shift_px)) + 1
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * reach + 1,) * 2)
    near = (cv2.dilate(mask.astype(np.uint8), kernel).astype(bool)
            & ~cv2.erode(mask.astype(np.uint8), kernel).astype(bool))
    rows, cols = np.nonzero(near)
    tree = cKDTree(np.concatenate(points))
    distance, nearest = tree.query(np.column_stack([cols, rows]).astype(float))
    position = np.concatenate(positions)[nearest]
    curvature = np.concatenate(bends)[nearest]
    sign = np.where(smooth[rows, cols] >= 0.5, 1.0, -1.0)
    keep = distance <= settings.band_px + settings.max_shift_px
    index = (rows * mask.shape[1] + cols)[keep]
    segment = np.floor(position[keep]).astype(int)   # arc < length: within its outline
    return _Band(index, (sign * distance)[keep], segment, position[keep], curvature[keep],
                 tuple(outlines))


def _curvature(dense: np.ndarray, inward: np.ndarray, smoothing_px: float) -> np.ndarray:
    """(N,) curvature of a closed outline (N, 2) at each of its points, 1/px, smoothed along
    it over ``smoothing_px``: positive where it bends around the body (convex), negative
    where around the water; ``inward``: (H, W, 2) a field pointing into the body."""
    spacing = float(np.mean(np.hypot(*np.diff(dense, axis=0).T))) or 1.0
    points = gaussian_filter1d(dense, smoothing_px / spacing, axis=0, mode="wrap")
    velocity = (np.roll(points, -1, 0) - np.roll(points, 1, 0)) / 2
    acceleration = np.roll(points, -1, 0) - 2 * points + np.roll(points, 1, 0)
    speed = np.maximum(np.hypot(*velocity.T), 1e-9)
    bend = (velocity[:, 0] * acceleration[:, 1] - velocity[:, 1] * acceleration[:, 0]) / speed ** 3
    normal = np.column_stack([-velocity[:, 1], velocity[:, 0]]) / speed[:, None]
    rows = np.clip(np.round(dense[:, 1]).astype(int), 0, inward.shape[0] - 1)
    cols = np.clip(np.round(dense[:, 0]).astype(int), 0, inward.shape[1] - 1)
    side = np.sign(np.sum(normal * inward[rows, cols], axis=1))
    return bend * side


def _densified(line: np.ndarray, step_px: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """A closed or open polyline (N, 2) resampled to points at most ``step_px`` apart, and
    the arc length at each."""
    if not np.allclose(line[0], line[-1]):
        line = np.vstack([line, line[:1]])
    lengths = np.hypot(*np.diff(line, axis=0).T)
    arc = np.concatenate([[0.0], np.cumsum(lengths)])
    samples = np.arange(0.0, arc[-1], step_px)
    dense = np.column_stack([np.interp(samples, arc, line[:, 0]),
                             np.interp(samples, arc, line[:, 1])])
    return dense, samples


@dataclass(frozen=True)
class _Fits:
    """Per segment at one blur: the edge's outward shift, the water's level and the step's
    contrast, and whether the segment is trusted (module doc, step 4); the summed residual of
    every segment (the blur's score) and the residuals' robust SD."""

    shift: np.ndarray
    level: np.ndarray
    contrast: np.ndarray
    trusted: np.ndarray
    score: float
    noise: float


def _segment_fits(band: _Band, values: np.ndarray, sigma_e: float, shifts: np.ndarray,
                  rounds: int, settings: OutlineFitSettings) -> _Fits:
    """The profile fitted to each segment at blur ``sigma_e`` over its own grid of shifts
    (``shifts``: segments × shifts), after ``rounds`` of down-weighting what does not follow
    it (module doc, steps 3 and 4). Its score is the summed residual of every segment."""
    segments = shifts.shape[0]
    weights = np.ones_like(values)
    places = np.arange(len(values))
    profile = ndtr((band.distance[:, None] + shifts[band.segment]) / sigma_e)   # N × D
    rows = np.arange(segments)
    one_hot = csr_matrix((np.ones(len(values)), (band.segment, places)),
                         shape=(segments, len(values)))

    def fitted(weights: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                             np.ndarray]:
        rss, level, contrast = _least_squares(one_hot, profile, values, weights)
        best = np.argmin(rss, axis=1)
        residual = values - (level[rows, best][band.segment] + contrast[rows, best][
            band.segment] * profile[places, best[band.segment]])
        return rss, level, contrast, best, residual

    rss, level, contrast, best, residual = fitted(weights)
    for _round in range(rounds):
        noise = 1.4826 * float(np.median(np.abs(residual))) + 1e-6
        weights = np.clip(1.0 - (residual / (settings.robust_scale * noise)) ** 2, 0.0,
                          None) ** 2
        rss, level, contrast, best, residual = fitted(weights)
    noise = 1.4826 * float(np.median(np.abs(residual))) + 1e-6
    step_px = shifts[0, 1] - shifts[0, 0]
    shift = shifts[rows, best] + _parabola(rss, best) * step_px
    total = np.asarray(one_hot @ weights)
    mean = np.asarray(one_hot @ (weights * values)) / np.maximum(total, 1e-9)
    spread = np.asarray(one_hot @ (weights * values * values)) - total * mean ** 2
    explained = 1.0 - rss[rows, best] / np.maximum(spread, 1e-9)
    inside = np.asarray(one_hot @ ((band.distance > 0) * weights))
    outside = np.asarray(one_hot @ ((band.distance < 0) * weights))
    level, contrast = level[rows, best], contrast[rows, best]
    trusted = ((contrast >= settings.min_contrast) & (explained >= settings.min_explained)
               & (inside >= settings.min_side_pixels) & (outside >= settings.min_side_pixels))
    least = rss[rows, best]
    score = float(least[np.isfinite(least)].sum())
    return _Fits(shift, level, contrast, trusted, score, noise)


def _least_squares(one_hot: csr_matrix, profile: np.ndarray, values: np.ndarray,
                   weights: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per segment (the rows of ``one_hot``) and shift (the columns of ``profile``, N × D):
    the weighted least squares of value ≈ level + contrast × profile; its residual sum of
    squares (inf where the profile does not vary), level and contrast (each S × D)."""
    weighted = profile * weights[:, None]
    total = np.asarray(one_hot @ weights)[:, None]
    sum_v = np.asarray(one_hot @ (weights * values))[:, None]
    sum_vv = np.asarray(one_hot @ (weights * values * values))[:, None]
    sum_p = np.asarray(one_hot @ weighted)
    sum_pp = np.asarray(one_hot @ (weighted * profile))
    sum_vp = np.asarray(one_hot @ (weighted * values[:, None]))
    det = total * sum_pp - sum_p ** 2
    singular = det <= 1e-9 * np.maximum(total, 1.0) ** 2
    det = np.where(singular, 1.0, det)
    contrast = (total * sum_vp - sum_v * sum_p) / det
    level = (sum_v - contrast * sum_p) / np.maximum(total, 1e-9)
    rss = sum_vv - level * sum_v - contrast * sum_vp
    return np.where(singular, np.inf, rss), level, contrast


def _parabola(rss: np.ndarray, best: np.ndarray) -> np.ndarray:
    """Per segment, the sub-step offset of the minimum of a parabola through the best shift
    and its two neighbours (0 at the grid's ends)."""
    rows = np.arange(len(best))
    left = rss[rows, np.maximum(best - 1, 0)]
    middle = rss[rows, best]
    right = rss[rows, np.minimum(best + 1, rss.shape[1] - 1)]
    inner = ((best > 0) & (best < rss.shape[1] - 1) & np.isfinite(left) & np.isfinite(right)
             & np.isfinite(middle))
    left, middle, right = (np.where(inner, side, 0.0) for side in (left, middle, right))
    curvature = left - 2 * middle + right
    offset = np.where(inner & (curvature > 0),
                      0.5 * (left - right) / np.where(curvature > 0, curvature, 1.0), 0.0)
    return np.clip(offset, -0.5, 0.5)


def _along_outlines(fitted: np.ndarray, outlines: tuple[tuple[int, int], ...],
                    settings: OutlineFitSettings) -> np.ndarray:
    """The shifts smoothed along each (closed) outline and filled in where a segment showed
    no edge (module doc, step 4)."""
    smooth = np.zeros_like(fitted)
    for start, count in outlines:
        own = fitted[start:start + count]
        known = np.isfinite(own)
        if not known.any():
            continue
        if known.mean() < settings.min_fitted_share:
            smooth[start:start + count] = np.median(own[known])
            continue
        positions = np.flatnonzero(known)
        filled = np.interp(np.arange(count), positions, own[known], period=count)
        reach = settings.smoothing_segments
        stacked = np.stack([np.roll(filled, k) for k in range(-reach, reach + 1)])
        smooth[start:start + count] = np.median(stacked, axis=0)
    return smooth


def _decided_mask(mask: np.ndarray, band: _Band, values: np.ndarray, fits: _Fits,
                  sigma_e: float, settings: OutlineFitSettings) -> np.ndarray:
    """The mask with each band pixel decided by whether it is at least half the body's
    (module doc, step 5): its level between the local water's and body's, averaged with what
    the fitted edge predicts there by their certainties (the image's noise against the
    reference outline's pixel-scale error), against one half."""
    shift = _along_outlines(np.where(fits.trusted, fits.shift, np.nan), band.outlines,
                            settings)
    level = _along_outlines(np.where(fits.trusted, fits.level, np.nan), band.outlines,
                            settings)
    contrast = _along_outlines(np.where(fits.trusted, fits.contrast, np.nan), band.outlines,
                               settings)
    local_contrast = np.maximum(_at_places(contrast, band), 1e-6)
    share = (values - _at_places(level, band)) / local_contrast
    predicted = ndtr((band.distance + _at_places(shift, band)) / sigma_e)
    image_var = (fits.noise / local_contrast) ** 2
    model_var = (settings.reference_error_px / (sigma_e * np.sqrt(2 * np.pi))) ** 2
    blended = (share * model_var + predicted * image_var) / (model_var + image_var)
    # where a segment showed no edge, its neighbours' levels may not be the water beside it
    # (a seagrass patch, another animal): there the shifted outline alone decides
    blended = np.where(fits.trusted[band.segment], blended, predicted)
    # a blurred edge bending around the body is half-way a little inside it (module doc)
    half = 0.5 - HALF_LEVEL_PER_BEND * np.clip(band.curvature, -0.5, 0.5) * sigma_e
    moved = mask.copy().ravel()
    moved[band.index] = blended >= half
    return moved.reshape(mask.shape)


def _at_places(per_segment: np.ndarray, band: _Band) -> np.ndarray:
    """A per-segment quantity at each band pixel's place along its outline, linear between
    the segments' centres (around the closed outline)."""
    place = band.position - 0.5
    low = np.floor(place).astype(int)
    share = place - low
    starts = np.array([start for start, _ in band.outlines])
    counts = np.array([count for _, count in band.outlines])
    outline = np.searchsorted(starts, band.segment, side="right") - 1
    start, count = starts[outline], counts[outline]
    before = start + (low - start) % count
    after = start + (low + 1 - start) % count
    return (1 - share) * per_segment[before] + share * per_segment[after]
