"""Differentiable mesh renderer with DIB-R semantics, pure PyTorch on the CPU.

``rasterize`` (hard, no gradient) → ``interpolate`` (screen-space barycentrics with gradients)
→ ``shade`` (albedo texture, spherical-Gaussian light, water filter) and ``soft_mask`` (DIB-R
silhouette); ``render`` composes them. All work is on sparse (pixel, face) pair lists batched
over frames, so cost grows with the summed area of face boxes, never pixels × faces.
"""

# What the soft silhouette measures distances to (core/render/soft_mask.py); torch-free here so
# that configuration files validate without loading torch.
SOFT_PRIMITIVES = ("contour", "faces")
