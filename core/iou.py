"""Intersection over union of masks, one definition for the fit and the segmenters.

Two empty masks score 1: they agree completely (the animal is absent from both, e.g. a tracker
correctly reporting it lost). IoU is a measure of agreement, and 0 would count that agreement as
a total miss; the fit never meets the case, as it skips frames without a visible dolphin.
"""

from typing import TypeVar

Masks = TypeVar("Masks")  # numpy arrays or torch tensors: only operators common to both are used


def mask_iou(a: Masks, b: Masks) -> Masks:
    """(...) |a ∩ b| / |a ∪ b| of (..., H, W) bool masks; 1 where both are empty."""
    inter = (a & b).sum((-2, -1))
    union = (a | b).sum((-2, -1))
    both_empty = union == 0
    return (inter + both_empty) / (union + both_empty)
