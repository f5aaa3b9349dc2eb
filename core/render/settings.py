"""Raster settings and viewports.

Pixel frame (as in core/camera.py): pixel centres at integer coordinates, u to the right, v
down. A viewport is the window of the full frame that is rendered: a crop with top-left pixel
(x0, y0), per frame, and a common size.

Softness rule. The paper renders 720×480 frames with DIB-R's σinv = 1e5, box length 0.01 and
k = 40, where distances are in NDC (one NDC unit = W/2 = 360 px across). We measure distances
in pixels instead, isotropically, with the paper's horizontal softness:
``p = exp(−sigma_px · d_px²)``, ``sigma_px = σinv / (720/2)² ≈ 0.77 px⁻²``, and a margin of
``box_len · 720/2 = 3.6 px``. An edge therefore looks equally soft in pixels at every resolution
and in every ROI (in Kaolin's anisotropic NDC it would be 1.5× sharper vertically at 720×480).
"""

from dataclasses import dataclass

import torch

from dolphinfit.core.intrinsics import CameraIntrinsics
from dolphinfit.core.render import SOFT_PRIMITIVES

# The paper's DIB-R settings (arXiv 2504.15782, appendix; reference/rendering.md §3.2).
PAPER_SIGMA_INV = 1e5
PAPER_BOX_LEN = 0.01
PAPER_MAX_FACES_PER_PIXEL = 40
PAPER_WIDTH_PX = 720


@dataclass(frozen=True)
class RasterSettings:
    """DIB-R soft-mask parameters, given in the paper's NDC units at ``reference_width_px``."""

    sigma_inv: float = PAPER_SIGMA_INV          # NDC⁻², at reference_width_px
    box_len: float = PAPER_BOX_LEN              # NDC margin around each face's box
    max_faces_per_pixel: int = PAPER_MAX_FACES_PER_PIXEL  # k: first faces in index order
    reference_width_px: int = PAPER_WIDTH_PX
    max_pairs_per_chunk: int = 4_000_000        # memory bound of one pair-list chunk
    # what the soft mask measures distances to (core/render/soft_mask.py): "contour", the
    # mesh's contour edges, or "faces", every face as DIB-R does
    soft_primitives: str = "contour"

    def __post_init__(self) -> None:
        if self.soft_primitives not in SOFT_PRIMITIVES:
            raise ValueError(f"soft_primitives: one of {', '.join(SOFT_PRIMITIVES)}, got "
                             f"{self.soft_primitives!r}")

    @property
    def sigma_px(self) -> float:
        """Softness in px⁻², the same at every resolution (module docstring)."""
        return self.sigma_inv / (0.5 * self.reference_width_px) ** 2

    @property
    def margin_px(self) -> float:
        """Margin around each face's box in pixels beyond which a face has no soft influence."""
        return self.box_len * 0.5 * self.reference_width_px


@dataclass(frozen=True, eq=False)
class Viewport:
    """The rendered window of each frame: top-left pixel per frame, common size."""

    x0_px: torch.Tensor   # (T,) int64
    y0_px: torch.Tensor   # (T,) int64
    width_px: int
    height_px: int

    @classmethod
    def full_frame(cls, intrinsics: CameraIntrinsics, num_frames: int) -> "Viewport":
        """The whole image in every frame."""
        zeros = torch.zeros(num_frames, dtype=torch.int64)
        return cls(zeros, zeros.clone(), intrinsics.width_px, intrinsics.height_px)

    @property
    def num_frames(self) -> int:
        """T."""
        return self.x0_px.shape[0]

    @property
    def num_pixels(self) -> int:
        """Pixels per frame, H·W."""
        return self.width_px * self.height_px
