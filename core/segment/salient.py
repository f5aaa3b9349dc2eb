"""The salient-object network (U²-Net small) on a crop, through OpenCV's DNN module.

Input: the crop resized to 320 × 320, scaled by its maximum, normalised with the ImageNet
mean and SD (how the network was trained). Output: the fused side output, a per-pixel
probability of belonging to the salient object, resized back to the crop. It is used as it is,
not stretched to 0…1 (as background-removal tools do): on open water it stays near 0 (at most
0.002 on flat noisy water, measured), so a click on the water finds nothing instead of the
strongest ripple. The network is not promptable: which salient region is the animal is
decided by the caller.
"""

import cv2
import numpy as np

from dolphinfit.core.segment.weights import U2NETP, WheelWeights, installed_path

INPUT_SIZE_PX = 320
MEAN_RGB = np.array([0.485, 0.456, 0.406], dtype=np.float32)
SD_RGB = np.array([0.229, 0.224, 0.225], dtype=np.float32)


class SalientNet:
    """One loaded network; ``saliency`` is not thread-safe (one net per worker)."""

    def __init__(self, weights: WheelWeights = U2NETP) -> None:
        self.net = cv2.dnn.readNetFromONNX(str(installed_path(weights)))

    def saliency(self, crop_rgb: np.ndarray) -> np.ndarray:
        """(h, w) float32 saliency in 0…1 of an (h, w, 3) uint8 RGB crop."""
        height, width = crop_rgb.shape[:2]
        small = cv2.resize(crop_rgb, (INPUT_SIZE_PX, INPUT_SIZE_PX),
                           interpolation=cv2.INTER_AREA).astype(np.float32)
        small /= max(float(small.max()), 1.0)
        blob = ((small - MEAN_RGB) / SD_RGB).transpose(2, 0, 1)[None]
        self.net.setInput(np.ascontiguousarray(blob))
        probability = self.net.forward()[0, 0].astype(np.float32)
        return cv2.resize(probability, (width, height), interpolation=cv2.INTER_LINEAR)
