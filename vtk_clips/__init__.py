"""Synthetic clips drawn by VTK's own rasterizer, not dolphinfit's: the third bench split.

The tuning and held-out splits are drawn by ``core.synth``, whose blur, anti-aliasing, shading
and water the networks learnt from. This package draws the same kind of scene another way,
so that a figure measured on it says how the product does on footage no one here rendered:
OpenGL's rasterizer (EGL, off screen) with 8× multisampling, VTK's Phong shading of vertex
colours under its own lights, water as stacked translucent layers and a plain surface. It lies
outside ``core`` because the engine never imports VTK; ``core.bench`` reaches it through the
renderer registry (``core.bench.scenario.register_renderer``), which importing this package
fills.
"""

from dolphinfit.core.bench.scenario import register_renderer
from dolphinfit.core.bench.vtk_split import VTK_RENDERER
from dolphinfit.vtk_clips.clip import make_vtk_clip

register_renderer(VTK_RENDERER, make_vtk_clip)
