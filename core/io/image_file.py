"""Still image files as (H, W, 3) uint8 RGB: whatever OpenCV decodes, and DNG raw files through
the JPEG preview they embed.

A DNG's raw data needs demosaicing, colour and tone processing that is out of scope here; DNG
writers embed a rendered JPEG preview (often full size). The largest embedded JPEG with a DCT
frame (baseline, extended or progressive) is read; lossless-JPEG raw tiles are skipped.
Images of 16 bits per channel come out scaled to 8 bits.
"""

from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.errors import InputError

DNG_SUFFIX = ".dng"
IMAGE_SUFFIXES = (".jpg", ".jpeg", ".png", ".tif", ".tiff", ".bmp", DNG_SUFFIX)
JPEG_SOI = b"\xff\xd8\xff"  # start of image, then the first marker's 0xFF
DCT_FRAME_MARKERS = {0xC0, 0xC1, 0xC2}  # SOF0 baseline, SOF1 extended, SOF2 progressive
STANDALONE_MARKERS = {0x01, *range(0xD0, 0xD8)}  # TEM, RST0–7: no length field


def read_image(path: Path) -> np.ndarray:
    """The image at ``path`` as (H, W, 3) uint8 RGB; InputError naming the file otherwise."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror or exc})") from exc
    if path.suffix.lower() == DNG_SUFFIX:
        bgr = _largest_embedded_jpeg(data)
        if bgr is None:
            raise InputError(f"{path}: no embedded JPEG preview could be decoded "
                             "(dolphinfit reads a DNG's preview, not its raw data)")
    else:
        bgr = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
        if bgr is None:
            raise InputError(f"{path}: not an image that OpenCV can decode "
                             "(damaged, or not an image file)")
    return cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)


def _largest_embedded_jpeg(data: bytes) -> np.ndarray | None:
    """The decodable DCT JPEG with the most pixels among those starting anywhere in ``data``
    (BGR), None if there is none. Each is decoded from its start marker; the decoder stops at
    its end marker, so nested thumbnails and trailing bytes do no harm."""
    buffer = np.frombuffer(data, np.uint8)
    best = None
    start = data.find(JPEG_SOI)
    while start >= 0:
        if _frame_marker(data, start) in DCT_FRAME_MARKERS:
            bgr = cv2.imdecode(buffer[start:], cv2.IMREAD_COLOR)
            if bgr is not None and (best is None or bgr.shape[0] * bgr.shape[1]
                                    > best.shape[0] * best.shape[1]):
                best = bgr
        start = data.find(JPEG_SOI, start + 1)
    return best


def _frame_marker(data: bytes, start: int) -> int | None:
    """The start-of-frame marker (0xC0…0xCF but DHT, JPG, DAC) of the JPEG whose start-of-image
    marker is at ``start``, walking its marker segments; None if malformed."""
    pos = start + 2
    while pos + 4 <= len(data) and data[pos] == 0xFF:
        marker = data[pos + 1]
        if marker == 0xFF:  # fill byte
            pos += 1
        elif marker in STANDALONE_MARKERS:
            pos += 2
        elif 0xC0 <= marker <= 0xCF and marker not in (0xC4, 0xC8, 0xCC):
            return marker
        elif marker in (0xD9, 0xDA):  # end of image or start of scan before any frame
            return None
        else:
            pos += 2 + int.from_bytes(data[pos + 2:pos + 4], "big")
    return None
