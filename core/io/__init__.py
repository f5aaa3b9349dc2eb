"""File formats: one module per format (meshes now; video, telemetry, masks and exports later)."""
