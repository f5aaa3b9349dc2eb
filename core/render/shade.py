"""Shading of covered pixels: albedo texture, spherical-Gaussian light, water filter.

Formulas from reference/rendering.md §3.3–§4: bilinear texture lookup (``align_corners=False``,
border padding), diffuse light as the inner product of the clamped-cosine lobe
G(·; n, 2.133, 1.17) with each light lobe (DIB-R++), radiance = albedo / π · E(n), and the
paper's water filter Ĉ = C ∘ exp(min(z, 0) · F_water) with z the world height in metres.
"""

import math
from dataclasses import dataclass

import torch
import torch.nn.functional as F


COSINE_LOBE_SHARPNESS = 2.133   # clamped cosine fitted as one SG lobe (Wang et al. 2009)
COSINE_LOBE_AMPLITUDE = 1.17


@dataclass(frozen=True, eq=False)
class SGLight:
    """A few spherical-Gaussian light lobes G(ω) = μ·exp(λ(ω·ξ − 1))."""

    axes: torch.Tensor        # (K, 3) unit directions ξ (towards the light), world frame
    sharpness: torch.Tensor   # (K,) λ > 0
    amplitude: torch.Tensor   # (K, 3) RGB μ ≥ 0

    @classmethod
    def overhead_sun(cls, dtype: torch.dtype = torch.float32,
                     device: torch.device | str = "cpu") -> "SGLight":
        """A sun high in the sky, a broad sky lobe and a faint upwelling from below."""
        like = dict(dtype=dtype, device=device)
        axes = torch.tensor([[0.25, 0.15, 0.95], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]], **like)
        return cls(axes=axes / torch.linalg.vector_norm(axes, dim=-1, keepdim=True),
                   sharpness=torch.tensor([6.0, 0.8, 1.5], **like),
                   amplitude=torch.tensor([[1.9, 1.85, 1.75], [0.55, 0.6, 0.65],
                                           [0.12, 0.14, 0.15]], **like))


def sg_irradiance(normals: torch.Tensor, light: SGLight) -> torch.Tensor:
    """(N, 3) diffuse irradiance E(n) = max(0, Σ_k ⟨cosine lobe about n, light lobe k⟩) at
    unit ``normals`` (N, 3).

    The inner product of two lobes is ∫ G_a G_b dω = 2π μa μb e^{dm − λa − λb} (1 − e^{−2dm})
    / dm with dm = ‖λa ξa + λb ξb‖ = √(λa² + λb² + 2 λa λb ξa·ξb) for unit axes, so every
    lobe's dot product with every normal is one matrix product, and so is the sum over lobes.
    """
    sharp_a = COSINE_LOBE_SHARPNESS
    sharp_b = light.sharpness                                              # (K,)
    cosine = normals @ light.axes.T                                        # (N, K)
    dm = (sharp_a ** 2 + sharp_b ** 2 + 2.0 * sharp_a * sharp_b * cosine).clamp(min=1e-24).sqrt()
    scalar = (2.0 * math.pi * COSINE_LOBE_AMPLITUDE * torch.exp(dm - sharp_a - sharp_b)
              * (-torch.expm1(-2.0 * dm)) / dm)
    return (scalar @ light.amplitude).clamp(min=0.0)


def sample_texture(texture: torch.Tensor, uv: torch.Tensor) -> torch.Tensor:
    """(N, C) bilinear samples of ``texture`` (Ht, Wt, C) at ``uv`` (N, 2).

    u runs along columns, v along rows from the top; (0, 0) is the top-left corner of the
    top-left texel (``align_corners=False``); outside [0, 1] the border texel repeats.
    """
    if not bool(torch.isfinite(uv.detach()).all()):
        raise ValueError("texture coordinates must be finite (grid_sample's backward crashes "
                         "on NaN)")
    grid = (2.0 * uv - 1.0).reshape(1, 1, -1, 2)
    image = texture.permute(2, 0, 1)[None]
    sampled = F.grid_sample(image, grid.to(image.dtype), mode="bilinear", padding_mode="border",
                            align_corners=False)
    return sampled[0, :, 0].T


def water_filter(colour: torch.Tensor, height_m: torch.Tensor,
                 f_water: torch.Tensor) -> torch.Tensor:
    """The paper's transmission Ĉ = C ∘ exp(min(z, 0) · F_water); colour (N, 3), z (N,)."""
    return colour * torch.exp(height_m.clamp(max=0.0)[:, None] * f_water)


def vertex_normals(verts: torch.Tensor, faces: torch.Tensor) -> torch.Tensor:
    """(T, V, 3) unit area-weighted vertex normals of meshes (T, V, 3), outward winding.

    Coordinates are handled as separate (T, F) planes: the cross product and the sums over
    each vertex's faces then run on contiguous arrays, twice as fast forward and backward as
    on (T, F, 3) corner tensors.
    """
    num_frames, num_verts = verts.shape[:2]
    corner_major = faces.T.reshape(-1)                                   # (3F,)
    corners = [coord.index_select(1, corner_major).reshape(num_frames, 3, -1).unbind(1)
               for coord in verts.unbind(-1)]                            # [x, y, z][corner]
    edge_1 = [c[1] - c[0] for c in corners]
    edge_2 = [c[2] - c[0] for c in corners]
    face_normals = [edge_1[1] * edge_2[2] - edge_1[2] * edge_2[1],     # 2·area, (T, F) each
                    edge_1[2] * edge_2[0] - edge_1[0] * edge_2[2],
                    edge_1[0] * edge_2[1] - edge_1[1] * edge_2[0]]
    normals = torch.stack([torch.zeros(num_frames, num_verts, dtype=verts.dtype,
                                       device=verts.device)
                           .index_add(1, corner_major, component.repeat(1, 3))
                           for component in face_normals], dim=-1)
    return normals / torch.linalg.vector_norm(normals, dim=-1, keepdim=True).clamp(min=1e-20)
