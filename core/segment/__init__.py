"""Dolphin masks from video: the segmenter interface, the built-in tracker and its measurement.

The built-in tracker (``tracker.py``) needs no network and no model weights. Learned
segmenters (the SAM family) cannot run here: no package ships their weights and torchvision
does not import with the CPU torch (reference/platform.md §7). Their masks come in through
``core/io/masks.py`` instead, or through a wrapper that implements ``Segmenter``.
"""
