"""The camera dialog's pixel size: tied to the sensor width at the image width, typed for a
still of no known camera, shown for a photo's own camera."""

from pathlib import Path

import pytest
from PySide6.QtWidgets import QAbstractSpinBox, QLabel

from dolphinfit.core.project.photo_camera import photo_camera
from dolphinfit.ui.dialogs.camera_dialog import CameraDialog

from .test_dialogs import child, ok_button, show, type_into

MINKE = Path(__file__).parents[1] / "data" / "real" / "minke" / "demo.JPG"
MINKE_SIZE = (2978, 1985)


def spin(dialog: CameraDialog, name: str) -> QAbstractSpinBox:
    return child(dialog, QAbstractSpinBox, name)


def test_a_still_of_unknown_camera_takes_a_focal_length_and_a_pixel_size(qtbot):
    """35 mm and 3.9167 µm typed: sensor width 3.9167 µm × 2978 px, the user's own values
    (not approximate), 3.18 mm per pixel at 28.4 m."""
    dialog = show(qtbot, CameraDialog(None, None, *MINKE_SIZE))
    derived = child(dialog, QLabel, "derived")
    assert derived.text().startswith("Camera unknown") and not ok_button(dialog).isEnabled()
    assert spin(dialog, "focal_mm").text() == spin(dialog, "pixel_size_um").text() == "unknown"
    assert (spin(dialog, "image_width_px").value(), spin(dialog, "image_height_px").value()) \
        == MINKE_SIZE

    type_into(qtbot, spin(dialog, "focal_mm"), "35")
    assert dialog.camera is None and not ok_button(dialog).isEnabled()   # no pixel size yet
    type_into(qtbot, spin(dialog, "pixel_size_um"), "3.9167")
    camera = dialog.camera
    assert ok_button(dialog).isEnabled() and not camera.approximate
    assert camera.focal_mm == 35.0 and camera.image_width_px == 2978
    assert camera.sensor_width_mm == pytest.approx(3.9167e-3 * 2978, abs=5e-5)
    assert spin(dialog, "sensor_width_mm").value() == pytest.approx(11.6639, abs=1e-4)
    assert camera.intrinsics().gsd_m_per_px(28.4) * 1000 == pytest.approx(3.18, rel=0.005)
    assert "Focal length 8936." in derived.text()


def test_the_photos_own_camera_shows_its_pixel_size_and_origin(qtbot):
    camera, _ = photo_camera(MINKE, *MINKE_SIZE)
    dialog = show(qtbot, CameraDialog(camera, None, *MINKE_SIZE))
    assert spin(dialog, "pixel_size_um").value() == pytest.approx(3.9167, abs=1e-4)
    assert "from the photo's EXIF: SONY ILCE-5100, 35 mm, pixel 3.92 µm" in \
        child(dialog, QLabel, "derived").text()
    type_into(qtbot, spin(dialog, "sensor_width_mm"), "14.89")   # 5 µm pixels
    assert spin(dialog, "pixel_size_um").value() == pytest.approx(5.0, abs=1e-4)
    assert dialog.camera.sensor_width_mm == 14.89 and not dialog.camera.approximate
