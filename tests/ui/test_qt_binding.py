"""The Qt binding keeps Python's reference counts: a void call must not eat a reference to
None (PySide6 6.12.0 on Python 3.11 did, and the app aborted after some 90 000 calls)."""

import sys

from PySide6.QtWidgets import QLabel


def test_void_qt_calls_keep_none_alive(qtbot):
    label = QLabel()
    qtbot.addWidget(label)
    before = sys.getrefcount(None)
    for _ in range(2000):
        label.setText("x")
    assert sys.getrefcount(None) > before - 200
