"""Synthetic drone clips of a dolphin with known truth, for tests, the demo and benchmarks.

A clip renders the parametric model swimming under a nadir camera over a procedural sea and
writes the video, true masks, part masks, altitude CSV, a DJI-style SRT and ``truth.json``.
Effects the fit does not model (shape outside β's span, a finer smoother mesh, scattering water,
refraction, ripples, glints, compression) can be switched on to test it honestly, and so can
the look of real footage: light-grey colouration, water presets and a seabed, sun glitter, wet
highlights, a second animal, white water and bending turns.
"""
