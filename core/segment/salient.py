"""The salient-object network (U²-Net small) on a crop, through ONNX Runtime on the CPU.

Input: the crop resized to 320 × 320, scaled by its maximum, normalised with the ImageNet
mean and SD (how the network was trained). Output: the fused side output, a per-pixel
probability of belonging to the salient object, resized back to the crop. It is used as it is,
not stretched to 0…1 (as background-removal tools do): on open water it stays near 0 (at most
0.002 on flat noisy water, measured), so a click on the water finds nothing instead of the
strongest ripple. The network is not promptable: which salient region is the animal is
decided by the caller.

ONNX Runtime gives OpenCV's DNN module's probabilities to 1e-5 in about 0.26 s a look on two
cores against 0.39 s. Its threads sleep between looks instead of spinning: spinning took the
cores from the torch work that runs between them (the edge network, the fit).
"""

import cv2
import numpy as np
import onnxruntime
import torch

from dolphinfit.core.segment.weights import U2NETP, WheelWeights, installed_path

INPUT_SIZE_PX = 320
MEAN_RGB = np.array([0.485, 0.456, 0.406], dtype=np.float32)
SD_RGB = np.array([0.229, 0.224, 0.225], dtype=np.float32)


def _session(weights: WheelWeights) -> onnxruntime.InferenceSession:
    """A CPU session on the installed weights, with as many threads as torch has (the
    process's setting, core.runtime)."""
    options = onnxruntime.SessionOptions()
    options.intra_op_num_threads = torch.get_num_threads()
    options.inter_op_num_threads = 1
    options.add_session_config_entry("session.intra_op.allow_spinning", "0")
    return onnxruntime.InferenceSession(str(installed_path(weights)), options,
                                        providers=["CPUExecutionProvider"])


class SalientNet:
    """One loaded network; ``saliency`` is not thread-safe (one net per worker)."""

    def __init__(self, weights: WheelWeights = U2NETP) -> None:
        self.session = _session(weights)
        self.input_name = self.session.get_inputs()[0].name
        self.output_name = self.session.get_outputs()[0].name   # the fused side output

    def saliency(self, crop_rgb: np.ndarray) -> np.ndarray:
        """(h, w) float32 saliency in 0…1 of an (h, w, 3) uint8 RGB crop."""
        height, width = crop_rgb.shape[:2]
        small = cv2.resize(crop_rgb, (INPUT_SIZE_PX, INPUT_SIZE_PX),
                           interpolation=cv2.INTER_AREA).astype(np.float32)
        small /= max(float(small.max()), 1.0)
        blob = np.ascontiguousarray(((small - MEAN_RGB) / SD_RGB).transpose(2, 0, 1)[None])
        probability = self.session.run([self.output_name], {self.input_name: blob})[0][0, 0]
        return cv2.resize(probability.astype(np.float32), (width, height),
                          interpolation=cv2.INTER_LINEAR)
