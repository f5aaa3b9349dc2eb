"""One animal seen in one sampled frame, and what the frame says about measuring it there.

The measures are taken on the scan's mask of the animal (the salient network's look, coarser
than the tracker's) and on the frame around it:

- **length** (px): the midline's arc length, rostrum tip to fluke notch
  (``mask_midline.midline_from_mask``). Within one animal's track a shorter length means a
  frame where the animal is pitched, diving, arched or partly out of sight: on the synthetic
  suite the frames where the true mask is longest are those whose elliptical volume is
  nearest the truth (``dolphinfit bench scan``).
- **straightness**: the midline's chord over its arc, 1 for a straight body. A bent body's
  widths are measured across a curve (Christiansen et al. 2016 measure only straight animals).
- **sharpness**: the variance of the Laplacian of the grey image over the animal and its
  outline (Pech-Pacheco et al. 2000; Pertuz et al. 2013 review it among focus measures):
  motion blur, a defocused frame or water over the animal lower it.
- **contrast**: the CIE76 colour difference between the animal's mean Lab colour and the
  water's in a ring around it: an animal at the surface stands out; one under water fades
  into it.
- **border** (px): the least distance from the animal to the frame's edge; an animal that
  touches it may be cut off.
"""

from dataclasses import dataclass

import cv2
import numpy as np

from dolphinfit.core.measure.mask_midline import arc_lengths, midline_from_mask
from dolphinfit.core.segment.seed import dilate

MIDLINE_POINTS = 9        # points of the midline the length and straightness are read from
OUTLINE_BAND_PX = 2       # the sharpness takes in this much of the water beyond the outline
RING_PX = (3, 8)          # the water's ring: from this far outside the animal to this far
MARGIN_PX = 12            # the box around the animal the measures look at


@dataclass(frozen=True)
class Sighting:
    """An animal in one sampled frame: where (its mask's bounding box ``x0, y0, width,
    height`` and centre, px) and the module doc's measures of it there."""

    frame_idx: int
    box: tuple[int, int, int, int]
    centre_px: tuple[float, float]
    length_px: float
    straightness: float
    sharpness: float
    contrast: float
    border_px: float


def sighting(frame_rgb: np.ndarray, mask: np.ndarray, frame_idx: int) -> Sighting | None:
    """The measures of the animal under ``mask`` (H, W bool) in a frame; None where its mask
    holds no midline (too small or empty)."""
    height, width = mask.shape
    x0, y0, box_w, box_h = cv2.boundingRect(mask.astype(np.uint8))
    rows = slice(max(0, y0 - MARGIN_PX), min(height, y0 + box_h + MARGIN_PX))
    cols = slice(max(0, x0 - MARGIN_PX), min(width, x0 + box_w + MARGIN_PX))
    local, crop = mask[rows, cols], frame_rgb[rows, cols]
    try:
        midline = midline_from_mask(local, MIDLINE_POINTS)
    except ValueError:
        return None
    arc = float(arc_lengths(midline)[-1])
    if not arc > 0:
        return None
    rows_in, cols_in = np.nonzero(mask)
    border = min(cols_in.min(), rows_in.min(), width - 1 - cols_in.max(),
                 height - 1 - rows_in.max())
    return Sighting(
        frame_idx=frame_idx, box=(x0, y0, box_w, box_h),
        centre_px=(float(cols_in.mean()), float(rows_in.mean())), length_px=arc,
        straightness=float(np.linalg.norm(midline[-1] - midline[0]) / arc),
        sharpness=laplacian_variance(crop, dilate(local, OUTLINE_BAND_PX)),
        contrast=colour_contrast(crop, local), border_px=float(border))


def laplacian_variance(crop_rgb: np.ndarray, region: np.ndarray) -> float:
    """The variance of the grey image's Laplacian over ``region`` (module doc)."""
    grey = cv2.cvtColor(np.ascontiguousarray(crop_rgb), cv2.COLOR_RGB2GRAY).astype(np.float32)
    return float(cv2.Laplacian(grey, cv2.CV_32F, ksize=3)[region].var())


def colour_contrast(crop_rgb: np.ndarray, animal: np.ndarray) -> float:
    """CIE76 ΔE between the animal's mean Lab colour and the water's in a ring around it
    (module doc); 0 where the crop leaves no ring."""
    ring = dilate(animal, RING_PX[1]) & ~dilate(animal, RING_PX[0])
    if not ring.any():
        return 0.0
    lab = cv2.cvtColor(np.ascontiguousarray(crop_rgb, dtype=np.float32) / 255.0,
                       cv2.COLOR_RGB2LAB)   # float input: L* 0–100, a* and b* unshifted
    return float(np.linalg.norm(lab[animal].mean(axis=0) - lab[ring].mean(axis=0)))
