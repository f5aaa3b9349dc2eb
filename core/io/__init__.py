"""File formats, one module per format: video, telemetry (DJI SRT, altitude CSV, laser logs),
masks, annotations, MorphoMetriX / CollatriX tables, meshes; atomic writes."""
