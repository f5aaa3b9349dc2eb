"""How a fit runs: loss weights, learning rates, stages and the switches beyond the paper.

Defaults are the paper's (Baieri et al., arXiv 2504.15782, appendix table; DESIGN.md §6) where
it gives them; every other default says why. Round-trips through JSON so each result records
how it was made.
"""

from dataclasses import asdict, dataclass, field, fields

import numpy as np

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.json_file import dataclass_from_json
from dolphinfit.core.io.video import Clip, frames_at_fps
from dolphinfit.core.limits import FPS, check_fields, count, one_of, time_window
from dolphinfit.core.measure.hw_ratios import DEFAULT_PRESET, FROM_MODEL
from dolphinfit.core.render import SOFT_PRIMITIVES

COLOUR_GEOMETRY = ("all_stages", "pose_stages", "none")
COUNT_MINIMUMS = {"heading_trial_steps": 0, "steps_global": 0, "steps_body": 0,
                  "steps_shape": 0, "heading_max_frames": 0, "shape_max_frames": 0,
                  "shape_full_steps": 0, "coarse_factor": 1, "coarse_steps": 0,
                  "roi_margin_px": 0, "fit_width_px": 0, "frames_per_chunk": 1,
                  "paper_width_px": 1, "max_faces_per_pixel": 1,
                  "max_frames": 1}  # whole-number fields


def fit_hw_table(spec: str) -> str | None:
    """A user's HW choice (``--hw``, the project's table) as ``FitConfig.hw_table``: "model"
    (the template's own ratios, for the elliptical baseline) is None here."""
    return None if spec == FROM_MODEL else spec


@dataclass(frozen=True)
class LossWeights:
    """Weights of the loss terms (the paper's, DESIGN.md §6)."""

    rgb: float = 1.0
    mask: float = 1.0
    # the paper's 2.0 held bodies straight through turns (turning clips' frame IoU 0.83–0.87
    # against 0.93–0.95 at 0.1; `bench fit --suite`, variant true_masks_paper_pose_prior)
    pose: float = 0.1
    # ours: the body's bend up or down, averaged over the fitted frames, stays near straight
    # (losses.pitch_bend_prior). A top view sees a lasting bend only as a shorter outline: on
    # a real minke still the fit bent the tail 30° down and came out 7.5–8.2 % longer than two
    # people measured it (`bench real --parts fit`); with it, 4.0–4.6 %
    pitch_bend: float = 1.0
    scale: float = 0.001
    scale_axes: float = 0.1
    scale_smooth: float = 5.0
    smooth_pos: float = 500.0
    smooth_rot: float = 500.0
    smooth_pose: float = 500.0
    direction: float = 0.1          # used only when use_direction_loss is on
    pyramid: float = 20.0           # wide-basin silhouette term, faded out (ours; rendering.md §8)
    vertical: float = 1.0           # the paper's vertical-motion nudge, when enabled
    # ours: the root's depth stays near FitConfig.init_depth_m. A top view sees size, not
    # depth: without it the pose stages matched the first size estimate's error with depth
    # (roots up to 0.4 m above the water or 0.8 m down: 2–4 % in length, 6–12 % in volume).
    depth: float = 1.0
    # ours: the root rises and sinks as its axis points (losses.glide_prior), so pitch cannot
    # stand in for length
    glide: float = 1.0
    # ours: the profile field's coefficients (core/model/profile_field.py) stay small and
    # vary smoothly from knot to knot
    profile: float = 0.001
    profile_smooth: float = 1.0     # ours: the same field's smoothness from knot to knot

    def __post_init__(self) -> None:
        check_fields(self, "fit option weights.", minimum={f.name: 0.0 for f in fields(self)})


@dataclass(frozen=True)
class LearningRates:
    """Adam learning rates per parameter group (the paper's)."""

    pose: float = 0.01
    shape: float = 0.01
    transl: float = 0.01
    albedo: float = 0.001
    water: float = 0.001
    light: float = 0.01

    def __post_init__(self) -> None:
        check_fields(self, "fit option learning_rates.",
                     minimum={f.name: 0.0 for f in fields(self)})


@dataclass(frozen=True)
class FitConfig:
    """Everything that decides a fit's outcome."""

    weights: LossWeights = field(default_factory=LossWeights)
    learning_rates: LearningRates = field(default_factory=LearningRates)
    steps_global: int = 40          # stage 1: root rotation and position
    steps_body: int = 40            # stage 2: + body pose
    steps_shape: int = 80           # stage 3: + overall and part shape, albedo, water, light
    heading_trial_steps: int = 15   # each of the two headings gets these, the better goes on
    # Frames rendered per step where fewer serve as well (0: all; evenly spread in time): the
    # heading trials only compare two headings; the shape stage fits shared shape, and its
    # last shape_full_steps steps render all its frames so each pose catches up with it.
    heading_max_frames: int = 8     # frames per step in the heading trials
    shape_max_frames: int = 16      # frames per step in the shape stage (above)
    shape_full_steps: int = 10      # the shape stage's last steps, on all its frames (above)
    # The heading trials and the first coarse_steps steps of the pose stages (global, then
    # body) render at 1/coarse_factor of the crops' resolution (1: native throughout); the
    # rest, and the shape stage, see native pixels.
    coarse_factor: int = 2
    coarse_steps: int = 40          # pose-stage steps at the coarse level (above)
    # Both switches beyond the paper were measured by `dolphinfit bench fit --suite` (8 clips):
    # crops halve the length error (median 0.70 % vs 1.18 %, worst 1.44 % vs 2.79 %) and fit
    # 2.1× faster, so they are on; refraction did not help yet (median volume error 4.98 % on
    # vs 4.34 % off), so it is off until it does.
    use_roi: bool = True            # native-resolution crops (False: whole frame at 720 px wide)
    use_refraction: bool = False    # flat-water refraction of submerged parts
    use_vertical_prior: bool = False   # the paper's v_surf / v_dive nudge
    use_direction_loss: bool = False   # heading follows the direction of motion
    smooth_order: int = 2           # 1: the paper's first differences; 2: constant velocity
    fps: float = 5.0                # frames fitted per second of video
    # A longer window is fitted at a lower rate, evenly spaced (io.video.frames_at_fps): on
    # seven 10-s clips 34 frames gave the volumes of 50 within 0.75 points in 22 % less fit
    # time, with a third fewer frames to track (decision 0020); it also bounds the time and
    # memory of a minute-long clip's fit.
    max_frames: int = 35
    start_s: float | None = None   # the part of the clip fitted, s (None: from its start)
    end_s: float | None = None     # … to this time, s (None: to its end)
    roi_margin_px: int = 24         # the crops' margin around the masks' box, px
    # An animal wider than twice this (its median widest width over the fitted frames, px)
    # is fitted at 1/2 of the video's resolution, 1/4 where it is twice as wide again, and so
    # on, so that it stays at least this wide (0: always at the video's resolution). More
    # pixels did not make the volume better: the tuning split at 4K (animals 43–82 px wide)
    # gave a mean |volume| error of 2.99 % at full resolution and 2.88 % with 8 of its 12
    # animals fitted at half; lengths came out 0.16 points shorter (mean −1.36 % against
    # −1.20 %). At 1080p the splits' animals (13–43 px) are fitted whole (`dolphinfit bench
    # fit --suite --frame-size 4k`, docs/decisions/0023).
    fit_width_px: int = 28
    paper_width_px: int = 720       # whole-frame width when use_roi is off (the paper's)
    init_depth_m: float = 0.15      # root depth at the start (back at the surface)
    # At most this many frames (at native resolution; as many pixels at coarse ones) are
    # rendered per forward/backward: bounds memory, and cancel is honoured between chunks,
    # which run on the cores side by side (engine.equal_chunks).
    frames_per_chunk: int = 16
    # The paper's k = 40 faces per pixel, taken in face-index order, binds at most outline
    # pixels of our crops (hundreds of candidates) and biases the silhouette gradient: on a
    # synthetic clip the overall scale drifted −11 % in 30 steps while the loss rose. With the
    # cap lifted the same steps lower the loss and move the scale towards the truth.
    max_faces_per_pixel: int = 1000
    # What the soft silhouette measures distances to (core/render/soft_mask.py): "contour"
    # (the mesh's contour edges; default, measured by `dolphinfit bench fit --speed`) or
    # "faces" (every face within the margin, DIB-R's and the paper's).
    soft_primitives: str = "contour"
    # Frames the pose stages cannot explain (deep dives seen edge-on, pitched bodies) would
    # bias the shared shape: the shape stage uses frames whose IoU after the pose stages is at
    # least the clip's median minus this margin.
    shape_iou_margin: float = 0.05
    # Scale of the renderer's edge profile given to the soft targets (target.py). 0 is a hard
    # target (widths came out 10 % narrow on a synthetic clip), 1 the measured profile. An
    # empirical calibration: with the depth prior, 0.92 makes the fit's own volume error
    # (its error minus the clip's hidden-height floor) average +0.1 % over the suite (0.78:
    # −3.7 %, 0.85: −1.8 %, 1.0: +1.8 %; `dolphinfit bench fit --suite`, docs/decisions/0010). 0.78 was
    # set while depth drifted with size.
    target_edge_scale: float = 0.92
    # Which stages the colour term's gradient moves the geometry in (pose, position, shape):
    # the lit model's shading and water-depth cue. "all_stages" is the paper's; with
    # "pose_stages" the shape stage's colour term fits albedo, water and light only, with
    # "none" it does so everywhere. Measured by `dolphinfit bench fit --suite` (docs/decisions/0006): in
    # the shape stage the cue traded silhouette for colour in a flat valley whose end float
    # order picked (grey_green_high −15.9 % or −7.7 % volume by chunk size), and in the pose
    # stages it made the animals about 2 % short.
    colour_geometry: str = "none"
    # A smooth field of width and height factors along the body (core/model/profile_field.py)
    # beside the per-part scales, fitted in the shape stage: a width profile that bends within
    # a part (the root part alone spans 25–55 % of the body) is out of the parts' reach.
    profile_field: bool = True
    # The heights a top view cannot see: the fitted animal keeps its template's height/width
    # ratio at each station (the axes prior ties a part's height to its width). None: the
    # built template's; an HW table (a preset name of core.measure.hw_ratios or a CSV path,
    # as `dolphinfit measure --hw`): the template reshaped to the table's ratios at the 5–85 %
    # stations first (core/model/sections.py), as the elliptical baseline takes them. The
    # default is the elliptical baseline's default table: on the suite's animals with other
    # heights than the template's the template's ratios made every volume low (mean −10.5 %,
    # `dolphinfit bench fit --suite`, variant true_masks_template_heights).
    hw_table: str | None = DEFAULT_PRESET

    def __post_init__(self) -> None:
        for name, minimum in COUNT_MINIMUMS.items():
            count(getattr(self, name), minimum, f"fit option {name}")
        check_fields(self, "fit option ", ranges={"fps": FPS},
                     minimum={"shape_iou_margin": 0.0, "target_edge_scale": 0.0})
        time_window(self.start_s, self.end_s, "fit option start_s", "fit option end_s")
        one_of(self.soft_primitives, SOFT_PRIMITIVES, "fit option soft_primitives")
        one_of(self.colour_geometry, COLOUR_GEOMETRY, "fit option colour_geometry")
        if self.hw_table == FROM_MODEL:
            raise InputError(f"fit option hw_table: {FROM_MODEL!r} would take the fit's "
                             f"heights from the fit itself; give an HW table")
        if self.smooth_order not in (1, 2):
            raise InputError(f"fit option smooth_order: 1 or 2, got {self.smooth_order}")

    @property
    def total_steps(self) -> int:
        """Optimisation steps over all stages, both heading trials included."""
        return (2 * self.heading_trial_steps + self.steps_global + self.steps_body
                + self.steps_shape)

    def frames_of(self, clip: Clip) -> np.ndarray:
        """The frames this fit takes from ``clip``: its window at its rate, at most
        ``max_frames`` of them, evenly spaced (before frames without a usable mask drop out)."""
        return frames_at_fps(clip, self.fps, self.start_s, self.end_s, self.max_frames)

    def colour_moves_geometry(self, stage: str) -> bool:
        """Whether the colour term's gradient reaches the geometry in ``stage``."""
        return (self.colour_geometry == "all_stages"
                or (self.colour_geometry == "pose_stages" and stage != "shape"))

    def to_json(self) -> dict:
        """JSON-ready dict."""
        return asdict(self)

    @classmethod
    def from_json(cls, data: dict) -> "FitConfig":
        """Inverse of :meth:`to_json`; unknown keys are an InputError, except ``seed``, which
        configurations written before it was removed carry (nothing in a fit is random)."""
        if isinstance(data, dict):
            data = {key: value for key, value in data.items() if key != "seed"}
        return dataclass_from_json(cls, data, "fit config")
