"""The fit's progress reports (core.progress).

One count for the whole fit: ``total`` is the number of optimisation steps (both heading
trials included, ``FitConfig.total_steps``). Stages come in the order of ``STAGE_ORDER``;
"prepare" (reading frames, placing the model) reports step 0, "result" (meshes, IoU) the step
the optimisation ended at, ``total`` for a complete fit. ``eta_s`` is the measured time per
step times the steps left while optimising, None in "prepare" and "result".
"""

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from dolphinfit.core.progress import Progress, ProgressCallback

PREPARE_STAGE = "prepare"
HEADING_STAGE = "heading"
RESULT_STAGE = "result"
STAGE_ORDER = (PREPARE_STAGE, HEADING_STAGE, "global", "body", "shape", RESULT_STAGE)
HEARTBEAT_S = 0.5   # within a long step, the last report is repeated this often
PREVIEW_INTERVAL_S = 1.0  # a step's report carries the current state at most this often


@dataclass(frozen=True, eq=False)
class FitPreview:
    """The fit's current state for display, what core.fit.motion and core.fit.pose_mesh pose
    at any clip frame (float32, metres, world frame)."""

    frame_idx: np.ndarray    # (T,) fitted clip frames
    transl: np.ndarray       # (T, 3) root joint positions
    pose_aa: np.ndarray      # (T, M, 3) axis-angle per part
    betas: np.ndarray        # (M, 4) part log scales, overall scale included
    rest_verts: np.ndarray   # (V, 3) the shape in the rest pose


class FitReporter:
    """Counts optimisation steps and sends a fit's reports to ``callback``."""

    def __init__(self, total: int, callback: ProgressCallback | None) -> None:
        self.total, self.callback = total, callback
        self.step = 0
        self.stage, self.message = PREPARE_STAGE, ""
        self.metrics: Mapping[str, float] = {}
        self._rate_started: float | None = None
        self._last_sent = time.perf_counter()
        self.preview_source: Callable[[], FitPreview] | None = None  # set by the running stage
        self._last_preview = -math.inf

    def step_started(self) -> None:
        """Start the rate's clock at the first optimisation step."""
        if self._rate_started is None:
            self._rate_started = time.perf_counter()

    def step_done(self, stage: str, terms: Mapping[str, float], mean_iou: float) -> None:
        """One more optimisation step, with its loss terms and mean IoU."""
        self.step += 1
        preview = None
        now = time.perf_counter()
        if (self.callback is not None and self.preview_source is not None
                and now - self._last_preview >= PREVIEW_INTERVAL_S):
            preview, self._last_preview = self.preview_source(), now
        self.report(stage, f"mean IoU {mean_iou:.3f}", {**terms, "mean_iou": mean_iou},
                    preview)

    def report(self, stage: str, message: str, metrics: Mapping[str, float] | None = None,
               preview: FitPreview | None = None) -> None:
        """Send where the fit is now (with a preview of its state, if given)."""
        self.stage, self.message, self.metrics = stage, message, metrics or {}
        self._send(preview)

    def heartbeat(self) -> None:
        """Repeat the last report if it is older than HEARTBEAT_S (keeps the ETA fresh)."""
        if time.perf_counter() - self._last_sent >= HEARTBEAT_S:
            self._send()

    def eta_s(self) -> float | None:
        """Seconds left at the measured rate; None outside the optimisation."""
        if self._rate_started is None or self.step == 0 or self.stage in (PREPARE_STAGE,
                                                                          RESULT_STAGE):
            return None
        per_step = (time.perf_counter() - self._rate_started) / self.step
        return per_step * (self.total - self.step)

    def _send(self, preview: FitPreview | None = None) -> None:
        self._last_sent = time.perf_counter()
        if self.callback is not None:
            self.callback(Progress(self.stage, self.step, self.total, self.message,
                                   self.eta_s(), dict(self.metrics), preview))
