"""Flat enumeration of the pixels inside many integer boxes (ragged → flat pair lists)."""

from collections.abc import Iterator
from dataclasses import dataclass

import torch


@dataclass(frozen=True)
class BoxPairs:
    """One (box, pixel) pair per pixel of every box."""

    owner: torch.Tensor   # (P,) int64 index of the box
    col: torch.Tensor     # (P,) int64 pixel column
    row: torch.Tensor     # (P,) int64 pixel row


def box_pair_chunks(col_min: torch.Tensor, col_max: torch.Tensor, row_min: torch.Tensor,
                    row_max: torch.Tensor, max_pairs: int) -> Iterator[BoxPairs]:
    """Pixels of the inclusive integer boxes (N,), in box order, chunked to ≤ ``max_pairs``.

    Cost is O(N + Σ box areas): counts, a cumulative sum and one ``repeat_interleave``. A
    single box larger than ``max_pairs`` forms a chunk of its own.
    """
    widths = (col_max - col_min + 1).clamp(min=0)
    counts = widths * (row_max - row_min + 1).clamp(min=0)
    ends = torch.cumsum(counts, 0)
    start_box = 0
    num_boxes = counts.shape[0]
    while start_box < num_boxes:
        offset = ends[start_box] - counts[start_box]
        stop_box = int(torch.searchsorted(ends, offset + max_pairs, right=True))
        stop_box = max(stop_box, start_box + 1)
        chunk = slice(start_box, stop_box)
        owner_local = torch.repeat_interleave(torch.arange(stop_box - start_box), counts[chunk])
        if owner_local.numel():
            local = (torch.arange(owner_local.shape[0])
                     - (ends[chunk] - counts[chunk] - offset)[owner_local])
            w = widths[chunk][owner_local]
            yield BoxPairs(owner=owner_local + start_box,
                           col=col_min[chunk][owner_local] + local % w,
                           row=row_min[chunk][owner_local] + torch.div(local, w,
                                                                       rounding_mode="floor"))
        start_box = stop_box
