"""Measurements: mesh volume, length and station profiles; the elliptical baseline, body
condition and mass, HW ratios and Monte Carlo uncertainty."""
