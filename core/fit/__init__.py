"""The model-based fit: clip + altitude + masks → metric 3D shape, motion, volume and mass.

``data`` cuts the frames and masks into regions of interest with exact intrinsics, ``init``
places the model from the masks, ``target`` makes soft targets comparable with DIB-R's soft
silhouette, ``losses`` holds the paper's terms, and ``engine.fit`` runs the staged optimisation.
"""
