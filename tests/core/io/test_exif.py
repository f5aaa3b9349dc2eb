"""A photo's camera from its EXIF: the real minke photograph's, focal-plane tags, none."""

from pathlib import Path

import cv2
import numpy as np
import pytest

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.exif import read_exif_camera

from .exif_still import write_still

MINKE = Path(__file__).parents[2] / "data" / "real" / "minke" / "demo.JPG"


def test_the_minke_photograph_names_its_sony_and_35_mm_lens():
    """MorphoMetriX's demo.JPG (a Lightroom crop) keeps the camera's Make, Model and focal
    length; a Sony writes no focal-plane resolution."""
    camera = read_exif_camera(MINKE)
    assert (camera.make, camera.model, camera.name) == ("SONY", "ILCE-5100", "SONY ILCE-5100")
    assert camera.focal_mm == 35.0 and camera.pixel_mm is None


def test_focal_plane_tags_give_the_pixel_size(tmp_path):
    """FocalPlaneXResolution in pixels per cm: 10 mm / 2553.4 = 3.9163 µm."""
    path = write_still(tmp_path / "p.jpg", np.zeros((200, 300, 3), np.uint8), 35.0,
                       0.0039163, make="Canon", model="Canon EOS 90D")
    camera = read_exif_camera(path)
    assert camera.name == "Canon EOS 90D" and camera.focal_mm == 35.0
    assert camera.pixel_mm == pytest.approx(0.0039163, rel=1e-6)


def test_a_photo_without_exif_names_no_camera(tmp_path):
    path = tmp_path / "plain.png"
    cv2.imwrite(str(path), np.zeros((20, 30, 3), np.uint8))
    assert read_exif_camera(path) is None


def test_an_implausible_focal_length_is_refused_naming_the_file_and_tag(tmp_path):
    path = write_still(tmp_path / "bad.jpg", np.zeros((20, 30, 3), np.uint8), 5000.0)
    with pytest.raises(InputError, match=r"bad\.jpg: EXIF FocalLength: 5000 mm is outside"):
        read_exif_camera(path)
