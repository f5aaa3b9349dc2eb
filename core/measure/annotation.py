"""Image annotations for the elliptical baseline: midline, width stations and edges, in pixels.

Pixels follow core/camera.py (OpenCV: centres at integer coordinates, u right, v down). An
:class:`Annotation` holds only pixels; the camera and altitude live apart in a
:class:`Calibration`, so a corrected altitude rescales every length without re-annotation
(DESIGN.md §3).

Geometry (reference/morphometrics.md §1, reference/ecosystem.md §1):

- The midline is an interpolating cubic spline through the clicks (it passes through every
  click), parameterised by cumulative chord length with not-a-knot ends. Both choices are
  symmetric under reversal, so clicking notch → rostrum gives the same curve, stations and
  perpendiculars (MorphoMetriX issue #8 was station geometry that depended on click order).
- Body length is the midline's arc length; station k sits at arc length fraction p_k (5 %, …,
  95 %) from the rostrum tip.
- A station's width is measured along its perpendicular: each edge point is projected onto the
  perpendicular, and the width is the distance between the two projections. Side A lies along
  the normal n = (−t_v, t_u) of the unit tangent t (rostrum → notch), which is the walker's
  right on screen (v down); side B is the other side. Mirror mode measures one side and
  doubles its distance from the midline.

Reference tools read the same clicks differently (:class:`Geometry`): MedidoR (de Oliveira
et al.) takes the body length along straight segments between the clicks and a width as the
straight distance between its two clicks, wherever they lie. ``MEDIDOR`` replays its
measurements to the hundredth of a pixel (``dolphinfit bench real``); the app and the CLI
measure with ``DEFAULT_GEOMETRY``.
"""

from dataclasses import dataclass

import numpy as np
from scipy.integrate import cumulative_simpson
from scipy.interpolate import CubicSpline
from scipy.ndimage import map_coordinates

from dolphinfit.core.camera_presets import CameraPreset
from dolphinfit.core.measure.stations import NUM_STATIONS, STATION_FRACTIONS

SIDES = ("A", "B")
ALTITUDE_SOURCES = ("laser", "barometer", "manual")  # recorded with the result (DESIGN §8)
# The altitude source of a reader's kind (core.io.altitude_samples); an altitude CSV's
# instrument is unknown.
ALTITUDE_SOURCE_OF_KIND = {"srt": "barometer", "laser": "laser", "constant": "manual"}

# Arc length: Simpson's rule on this many intervals per click span. The spline is a cubic
# per span, its speed smooth, so the error is far below a thousandth of a pixel.
ARC_INTERVALS_PER_SPAN = 256

# Mask edges: sample the perpendicular every MASK_STEP_PX and interpolate the crossing of the
# bilinearly interpolated mask through MASK_LEVEL (the boundary of a binary mask).
MASK_STEP_PX = 0.25
MASK_LEVEL = 0.5

MIDLINES = ("spline", "polyline")
WIDTH_RULES = ("perpendicular", "chord")


@dataclass(frozen=True)
class Geometry:
    """How length and widths are read off the clicks.

    ``midline``: "spline" (the interpolating spline, module doc) or "polyline" (straight
    segments between the clicks). ``widths``: "perpendicular" (both edge points projected
    onto the station's perpendicular) or "chord" (the straight distance between them).
    """

    midline: str = "spline"
    widths: str = "perpendicular"

    def __post_init__(self) -> None:
        if self.midline not in MIDLINES:
            raise ValueError(f"midline must be one of {MIDLINES}, got {self.midline!r}")
        if self.widths not in WIDTH_RULES:
            raise ValueError(f"widths must be one of {WIDTH_RULES}, got {self.widths!r}")


DEFAULT_GEOMETRY = Geometry()
MEDIDOR = Geometry(midline="polyline", widths="chord")


@dataclass(frozen=True, eq=False)
class Annotation:
    """One annotated frame, in image pixels (no calibration).

    ``midline_px``: (N, 2) float (u, v) clicks from the rostrum tip to the fluke notch, N ≥ 2.
    ``edges_px``: (S, 2, 2) float edge point of side A (index 0) and side B (index 1) at each
    station; NaN where a side is not marked (a station with no usable side is skipped).
    ``mirror_side``: None, or "A" / "B" to measure that side only and double it.
    """

    frame_idx: int
    midline_px: np.ndarray
    edges_px: np.ndarray
    mirror_side: str | None = None

    def __post_init__(self) -> None:
        midline = np.asarray(self.midline_px, dtype=np.float64)
        edges = np.asarray(self.edges_px, dtype=np.float64)
        if midline.ndim != 2 or midline.shape[1] != 2 or len(midline) < 2:
            raise ValueError(f"midline_px must be (N, 2) with N ≥ 2, got {midline.shape}")
        if not np.isfinite(midline).all():
            raise ValueError("midline_px must be finite")
        if np.any(np.linalg.norm(np.diff(midline, axis=0), axis=1) == 0):
            raise ValueError("midline_px has two identical consecutive clicks")
        if edges.shape != (NUM_STATIONS, 2, 2):
            raise ValueError(f"edges_px must be ({NUM_STATIONS}, 2, 2), got {edges.shape}")
        if self.mirror_side not in (None, *SIDES):
            raise ValueError(f"mirror_side must be None, 'A' or 'B', got {self.mirror_side!r}")
        object.__setattr__(self, "midline_px", midline)
        object.__setattr__(self, "edges_px", edges)


@dataclass(frozen=True)
class Calibration:
    """Camera and altitude of an annotated frame, kept apart from its pixels.

    ``camera``: the camera and video mode (a preset, or explicit values); ``preset_name``: the
    preset it was chosen by, None for explicit values. ``altitude_m``: camera height above the
    water, metres; ``altitude_source``: one of ``ALTITUDE_SOURCES``.
    """

    camera: CameraPreset
    preset_name: str | None
    altitude_m: float
    altitude_source: str

    def __post_init__(self) -> None:
        if not (np.isfinite(self.altitude_m) and self.altitude_m > 0):
            raise ValueError(f"altitude_m must be positive, got {self.altitude_m!r}")
        if self.altitude_source not in ALTITUDE_SOURCES:
            raise ValueError(f"altitude_source must be one of {ALTITUDE_SOURCES}, "
                             f"got {self.altitude_source!r}")

    @property
    def focal_px(self) -> float:
        """Focal length in pixels, focal_mm / sensor_width_mm × image_width_px (DESIGN §3)."""
        return self.camera.intrinsics().focal_px

    @property
    def m_per_px(self) -> float:
        """Metres per pixel on the water plane, altitude_m / focal_px."""
        return self.camera.intrinsics().gsd_m_per_px(self.altitude_m)


@dataclass(frozen=True, eq=False)
class Stations:
    """The width stations of a midline, in pixels.

    ``length_px``: arc length rostrum → notch. ``fractions``: (S,) arc-length fractions.
    ``points_px``: (S, 2) station points on the midline. ``normals``: (S, 2) unit
    perpendiculars pointing to side A.
    """

    length_px: float
    fractions: np.ndarray
    points_px: np.ndarray
    normals: np.ndarray


@dataclass(frozen=True, eq=False)
class PixelMeasurements:
    """What the elliptical baseline needs from an image: length and widths in pixels.

    ``widths_px``: (S,) float, NaN where a station was not measured. ``is_mirrored``: widths
    are one side doubled (their digitisation error is then twice one click's).
    """

    length_px: float
    widths_px: np.ndarray
    is_mirrored: bool


def midline_spline(midline_px: np.ndarray) -> CubicSpline:
    """The interpolating spline c(s) through the clicks, s = cumulative chord length (px).

    midline_px: (N, 2) float clicks. The spline passes through every click; with two clicks
    it is the straight segment.
    """
    chords = np.linalg.norm(np.diff(midline_px, axis=0), axis=1)
    knots = np.concatenate([[0.0], np.cumsum(chords)])
    return CubicSpline(knots, midline_px, axis=0, bc_type="not-a-knot")


def place_stations(midline_px: np.ndarray, fractions: np.ndarray = STATION_FRACTIONS,
                   midline: str = "spline") -> Stations:
    """Stations at equal arc length along the midline, with their perpendiculars.

    midline_px: (N, 2) clicks rostrum → notch; fractions: (S,) arc-length fractions in (0, 1);
    midline: "spline" or "polyline" (``Geometry.midline``).
    """
    if midline == "polyline":
        return _polyline_stations(midline_px, fractions)
    spline = midline_spline(midline_px)
    knots = spline.x
    grid = np.concatenate([
        np.linspace(a, b, ARC_INTERVALS_PER_SPAN + 1)[:-1] for a, b in zip(knots[:-1], knots[1:])
    ] + [knots[-1:]])
    speed = np.linalg.norm(spline(grid, 1), axis=1)
    arc = cumulative_simpson(speed, x=grid, initial=0.0)
    length_px = float(arc[-1])
    params = np.interp(np.asarray(fractions) * length_px, arc, grid)
    tangents = spline(params, 1)
    return _stations(length_px, fractions, spline(params), tangents)


def _polyline_stations(midline_px: np.ndarray, fractions: np.ndarray) -> Stations:
    """``place_stations`` along straight segments between the clicks; a station on a click
    takes the direction of the segment after it."""
    chords = np.diff(midline_px, axis=0)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(chords, axis=1))])
    at = np.asarray(fractions) * arc[-1]
    segment = np.clip(np.searchsorted(arc, at, side="right") - 1, 0, len(chords) - 1)
    share = (at - arc[segment]) / (arc[segment + 1] - arc[segment])
    points = midline_px[segment] + share[:, None] * chords[segment]
    return _stations(float(arc[-1]), fractions, points, chords[segment])


def _stations(length_px: float, fractions: np.ndarray, points_px: np.ndarray,
              tangents: np.ndarray) -> Stations:
    """Stations from their points and (unnormalised) tangents rostrum → notch."""
    tangents = tangents / np.linalg.norm(tangents, axis=1, keepdims=True)
    normals = np.stack([-tangents[:, 1], tangents[:, 0]], axis=1)
    return Stations(length_px=length_px, fractions=np.asarray(fractions, dtype=np.float64),
                    points_px=points_px, normals=normals)


def edge_offsets(stations: Stations, edges_px: np.ndarray) -> np.ndarray:
    """(S, 2) signed distance of each edge point from its station along the normal, px.

    edges_px: (S, 2, 2) side A / side B points. Side A lies at positive offsets; the component
    along the midline is dropped (the point is projected onto the perpendicular).
    """
    rel = edges_px - stations.points_px[:, None, :]
    return np.einsum("ski,si->sk", rel, stations.normals)  # sum over the pixel axis (u, v)


def station_widths(stations: Stations, edges_px: np.ndarray, mirror_side: str | None = None,
                   widths: str = "perpendicular") -> np.ndarray:
    """(S,) width at each station in pixels; NaN where a needed side is not marked.

    Both sides: the distance between the two projections on the perpendicular, or with
    ``widths="chord"`` between the two points themselves. Mirror mode ("A" or "B"): twice the
    distance of that side's projection (or point) from the station point.
    """
    if widths == "chord":
        if mirror_side is None:
            return np.linalg.norm(edges_px[:, 0] - edges_px[:, 1], axis=1)
        side = edges_px[:, SIDES.index(mirror_side)]
        return 2.0 * np.linalg.norm(side - stations.points_px, axis=1)
    offsets = edge_offsets(stations, edges_px)
    if mirror_side is None:
        return np.abs(offsets[:, 0] - offsets[:, 1])
    return 2.0 * np.abs(offsets[:, SIDES.index(mirror_side)])


def pixel_measurements(annotation: Annotation,
                       geometry: Geometry = DEFAULT_GEOMETRY) -> PixelMeasurements:
    """Length and station widths of an annotation, in pixels, read by ``geometry``."""
    stations = place_stations(annotation.midline_px, midline=geometry.midline)
    return PixelMeasurements(
        length_px=stations.length_px,
        widths_px=station_widths(stations, annotation.edges_px, annotation.mirror_side,
                                 geometry.widths),
        is_mirrored=annotation.mirror_side is not None,
    )


def suggest_edges(mask: np.ndarray, stations: Stations) -> np.ndarray:
    """(S, 2, 2) edge points where each perpendicular leaves the mask, side A then side B.

    mask: (H, W) bool or 0/1, True = dolphin, in the annotated image's pixels. Walking out
    from the station point along ±normal, the edge is the first crossing of the mask boundary
    (sub-pixel, by linear interpolation of the bilinear mask). NaN where the station point is
    off the mask or the walk leaves the image first (the edge is not visible). Fins joined to
    the outline (flippers near 25 %) are not told apart: review those stations.
    """
    image = np.asarray(mask, dtype=np.float64)
    radii = np.arange(0.0, stations.length_px / 2 + MASK_STEP_PX, MASK_STEP_PX)
    edges = np.full((len(stations.fractions), 2, 2), np.nan)
    for side_idx, sign in enumerate((1.0, -1.0)):
        # (S, R, 2) sample points (u, v) along each half-perpendicular
        ray = stations.points_px[:, None, :] + sign * radii[None, :, None] * \
            stations.normals[:, None, :]
        values = map_coordinates(image, [ray[..., 1], ray[..., 0]], order=1, mode="constant",
                                 cval=np.nan)
        for station_idx, profile in enumerate(values):
            radius = _first_crossing(profile, radii)
            if radius is not None:
                edges[station_idx, side_idx] = (stations.points_px[station_idx]
                                                + sign * radius * stations.normals[station_idx])
    return edges


def _first_crossing(profile: np.ndarray, radii: np.ndarray) -> float | None:
    """Radius where ``profile`` (R,) first drops below MASK_LEVEL; None if off-mask or unseen."""
    outside = ~(profile >= MASK_LEVEL)  # NaN (off the image) counts as outside
    if outside[0] or not outside.any():
        return None
    idx = int(np.argmax(outside))
    if np.isnan(profile[idx]):
        return None
    inner, outer = profile[idx - 1], profile[idx]
    frac = (inner - MASK_LEVEL) / (inner - outer)
    return float(radii[idx - 1] + frac * (radii[idx] - radii[idx - 1]))
