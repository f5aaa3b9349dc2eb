"""Flat enumeration of ragged ranges: (owner, position-within-owner) pairs, chunked.

Both the raster (pixels of each face's box) and the soft mask (uncovered pixels of each face's
box rows) turn per-owner counts into flat pair lists with one ``repeat_interleave``: cost
O(N + Σ counts), no Python loop over owners.
"""

from collections.abc import Iterator
from dataclasses import dataclass

import torch


@dataclass(frozen=True)
class RaggedChunk:
    """Pairs of one chunk: which owner, and the position within that owner's range."""

    owner: torch.Tensor   # (P,) int64, non-decreasing
    local: torch.Tensor   # (P,) int64, 0 … count[owner] − 1


def ragged_chunks(counts: torch.Tensor, max_pairs: int) -> Iterator[RaggedChunk]:
    """Enumerate ``counts`` (N,) ≥ 0 in owner order, at most ``max_pairs`` per chunk.

    An owner whose count alone exceeds ``max_pairs`` forms a chunk of its own.
    """
    ends = torch.cumsum(counts, 0)
    start, num_owners = 0, counts.shape[0]
    while start < num_owners:
        offset = ends[start] - counts[start]
        stop = max(int(torch.searchsorted(ends, offset + max_pairs, right=True)), start + 1)
        owner = torch.repeat_interleave(torch.arange(start, stop, device=counts.device),
                                        counts[start:stop])
        if owner.numel():
            yield RaggedChunk(owner=owner,
                              local=torch.arange(owner.shape[0], device=owner.device)
                              - (ends - counts - offset)[owner])
        start = stop


@dataclass(frozen=True)
class BoxPairs:
    """One (box, pixel) pair per pixel centre inside every box."""

    owner: torch.Tensor   # (P,) int64 index of the box
    col: torch.Tensor     # (P,) int64
    row: torch.Tensor     # (P,) int64


def box_pair_chunks(col_min: torch.Tensor, col_max: torch.Tensor, row_min: torch.Tensor,
                    row_max: torch.Tensor, max_pairs: int) -> Iterator[BoxPairs]:
    """Pixels of the inclusive integer boxes (N,), in box order, chunked."""
    widths = (col_max - col_min + 1).clamp(min=0)
    counts = widths * (row_max - row_min + 1).clamp(min=0)
    for chunk in ragged_chunks(counts, max_pairs):
        w = widths[chunk.owner]
        yield BoxPairs(owner=chunk.owner, col=col_min[chunk.owner] + chunk.local % w,
                       row=row_min[chunk.owner] + torch.div(chunk.local, w,
                                                            rounding_mode="floor"))
