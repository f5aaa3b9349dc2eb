"""Masks as regions of the frame: windows around them, crops, motion, and the colour models
near them; shared by the built-in tracker and the network tracker."""

from dataclasses import dataclass

import cv2
import numpy as np

from dolphinfit.core.segment.colour import ColourModel, to_lab
from dolphinfit.core.segment.seed import RING_OUTER_PX, colour_models, dilate, fill_holes


@dataclass(frozen=True, eq=False)
class MaskCrop:
    """A mask kept as its bounding box: top-left (row, col) and the (h, w) bool crop."""

    row0: int
    col0: int
    crop: np.ndarray

    def paste(self, height_px: int, width_px: int) -> np.ndarray:
        """The full (H, W) bool mask."""
        mask = np.zeros((height_px, width_px), bool)
        mask[self.row0:self.row0 + self.crop.shape[0],
             self.col0:self.col0 + self.crop.shape[1]] = self.crop
        return mask


def touches_border(mask: np.ndarray) -> bool:
    """Whether a (H, W) mask has a pixel in the frame's outermost row or column."""
    return bool(mask[0].any() or mask[-1].any() or mask[:, 0].any() or mask[:, -1].any())


def window(mask: np.ndarray, margin_px: int) -> tuple[slice, slice]:
    """Row and column slices of the mask's bounding box grown by ``margin_px``."""
    col0, row0, width, height = cv2.boundingRect(mask.astype(np.uint8))
    return (slice(max(0, row0 - margin_px), min(mask.shape[0], row0 + height + margin_px)),
            slice(max(0, col0 - margin_px), min(mask.shape[1], col0 + width + margin_px)))


def crop_of(mask: np.ndarray) -> MaskCrop:
    rows, cols = window(mask, 0)
    return MaskCrop(rows.start, cols.start, mask[rows, cols].copy())


def centroid(mask: np.ndarray) -> np.ndarray:
    """(x, y) centroid of a non-empty bool mask, pixels (its moments taken in its bounding
    box: the sums are whole numbers, so the result is the whole frame's to the bit)."""
    rows, cols = window(mask, 0)
    moments = cv2.moments(mask[rows, cols].astype(np.uint8), binaryImage=True)
    area = moments["m00"]
    return np.array([moments["m10"] + cols.start * area,
                     moments["m01"] + rows.start * area]) / area


def shifted(mask: np.ndarray, shift_px: np.ndarray) -> np.ndarray:
    """The mask moved by (dx, dy) pixels (rounded), cut at the frame's edges."""
    matrix = np.float32([[1, 0, round(shift_px[0])], [0, 1, round(shift_px[1])]])
    moved = cv2.warpAffine(mask.astype(np.uint8), matrix, mask.shape[::-1],
                           flags=cv2.INTER_NEAREST)
    return moved.astype(bool)


def models_near(frame_rgb: np.ndarray, mask: np.ndarray) -> tuple[ColourModel, ColourModel]:
    """``seed.colour_models`` computed in a window around the mask only."""
    rows, cols = window(mask, RING_OUTER_PX + 1)
    return colour_models(to_lab(frame_rgb[rows, cols]), mask[rows, cols])


def attached(candidate: np.ndarray, prediction: np.ndarray, gap_px: int) -> np.ndarray:
    """The component of ``candidate`` that overlaps ``prediction`` most, with the components
    within ``gap_px`` of it (flippers and flukes that a faint seam cuts off), holes filled."""
    count, labels = cv2.connectedComponents(candidate.astype(np.uint8), connectivity=8)
    if count < 2:
        return np.zeros_like(candidate)
    overlap = np.bincount(labels[prediction], minlength=count)[1:]
    if overlap.max() == 0:
        return np.zeros_like(candidate)
    main = labels == 1 + int(np.argmax(overlap))
    touching = np.unique(labels[dilate(main, gap_px)])
    return fill_holes(np.isin(labels, touching[touching > 0]))
