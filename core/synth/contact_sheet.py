"""A contact sheet of synthetic clips: each clip's middle frame, cropped around the target
animal at one ground scale, tiled with its name."""

import json
from pathlib import Path

import cv2
import numpy as np

from dolphinfit.core.synth.files import ClipFiles

CROP_M = 7.0            # side of each crop on the water, metres
TILE_PX = 420
COLUMNS = 4


def contact_sheet(clips: dict[str, ClipFiles], path: Path) -> np.ndarray:
    """Write (and return) a BGR sheet of the clips' middle frames to ``path``."""
    tiles = [_tile(name, files) for name, files in clips.items()]
    while len(tiles) % COLUMNS:
        tiles.append(np.zeros_like(tiles[0]))
    rows = [np.hstack(tiles[k:k + COLUMNS]) for k in range(0, len(tiles), COLUMNS)]
    sheet = np.vstack(rows)
    path.parent.mkdir(parents=True, exist_ok=True)
    cv2.imwrite(str(path), sheet)
    return sheet


def _tile(name: str, files: ClipFiles) -> np.ndarray:
    truth = json.loads(files.truth_json.read_text(encoding="utf-8"))
    config = truth["config"]
    middle = len(truth["frames"]) // 2
    capture = cv2.VideoCapture(str(files.video))
    capture.set(cv2.CAP_PROP_POS_FRAMES, middle)
    ok, frame = capture.read()
    capture.release()
    if not ok:
        raise ValueError(f"{files.video}: cannot read frame {middle}")
    mask = cv2.imread(str(files.masks_dir / f"{middle:06d}.png"), cv2.IMREAD_GRAYSCALE)
    height, width = mask.shape
    if mask.any():
        rows, cols = np.nonzero(mask)
        centre = (int(cols.mean()), int(rows.mean()))
    else:
        centre = (width // 2, height // 2)
    focal_px = config["focal_mm"] / config["sensor_width_mm"] * width
    half = int(CROP_M / truth["frames"][middle]["altitude_m"] * focal_px / 2)
    padded = cv2.copyMakeBorder(frame, half, half, half, half, cv2.BORDER_CONSTANT)
    crop = padded[centre[1]:centre[1] + 2 * half, centre[0]:centre[0] + 2 * half]
    tile = cv2.resize(crop, (TILE_PX, TILE_PX), interpolation=cv2.INTER_AREA)
    label = f"{name}  L {truth['length_m']:.2f} m, {config['altitude_m']:.0f} m"
    cv2.rectangle(tile, (0, 0), (TILE_PX, 24), (0, 0, 0), -1)
    cv2.putText(tile, label, (6, 17), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (255, 255, 255), 1,
                cv2.LINE_AA)
    return tile
