"""When a fit's figures cannot be trusted, and why: its status is then "unreliable" with the
reasons, wherever the result is shown (result.json, the command line's last line, a batch's
summary, the app), never "complete".

- **Too few frames**: under ``MIN_FRAMES`` fitted frames say little about a swimming animal
  (a pose seen once can be fitted by a wrong shape).
- **A poor fit**: a mean IoU of the model against the masks under ``MIN_MEAN_IOU`` (masks of a
  seagrass patch gave 0.61 on the bench suite: the masks may not show a dolphin at all).
- **A partial body**: masks under ``core.fit.whole_body.WHOLE_ELONGATION`` times as long as
  they are wide in the fitted frames (their median) show part of an animal.
- **Too few pixels**: an animal under ``MIN_WIDTH_PX`` wide at its widest, where each tenth
  of a pixel of outline is several per cent of volume (width and height both grow by twice
  the outline's error: 2 % per tenth of a pixel at 20 px).
"""

import numpy as np

from dolphinfit.core.fit.whole_body import WHOLE_ELONGATION

MIN_FRAMES = 5
MIN_MEAN_IOU = 0.7
MIN_WIDTH_PX = 20


def unreliable_reasons(frames: int, ious: np.ndarray, elongation: float,
                       width_px: float) -> tuple[str, ...]:
    """Why a fit of ``frames`` frames whose model meets its masks with ``ious`` (T,), masks
    ``elongation`` times as long as wide and an animal ``width_px`` wide (both medians over the
    fitted frames) cannot be trusted (module doc); none when it can."""
    mean_iou = float(np.mean(ious)) if len(ious) else 0.0
    reasons = []
    if frames < MIN_FRAMES:
        reasons.append(f"only {frames} frame(s) fitted (a fit needs {MIN_FRAMES})")
    if mean_iou < MIN_MEAN_IOU:
        reasons.append(f"a poor fit: the model meets the masks with a mean IoU of "
                       f"{mean_iou:.2f} (under {MIN_MEAN_IOU:.2f}); check that the masks show "
                       f"the dolphin")
    if elongation < WHOLE_ELONGATION:
        reasons.append(f"a partial body: the masks are only {elongation:.1f} times as long as "
                       f"the animal is wide (a whole dolphin: 4 to 6)")
    if width_px < MIN_WIDTH_PX:
        reasons.append(f"the animal is only {width_px:.0f} px wide at its widest (under "
                       f"{MIN_WIDTH_PX} px): each tenth of a pixel of outline moves the volume "
                       f"by about {100 * 4 * 0.1 / width_px:.0f} %")
    return tuple(reasons)
