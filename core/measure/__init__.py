"""Measurements: mesh volume, length and station profiles (and later the elliptical baseline,
body condition, mass and uncertainty)."""
