"""What ties a feature's widgets, workers and the project together: the fit, the masks,
playback."""
