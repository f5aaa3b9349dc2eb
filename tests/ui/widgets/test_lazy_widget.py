"""Heavy dock contents are built on first show, once."""

from PySide6.QtWidgets import QLabel

from dolphinfit.ui.widgets.lazy_widget import LazyWidget


def test_built_once_on_first_show(qtbot):
    made = []
    slot = LazyWidget(lambda: made.append(QLabel("real")) or made[-1], "placeholder")
    qtbot.addWidget(slot)
    assert slot.widget is None and made == []
    with qtbot.waitSignal(slot.built, timeout=1000):
        slot.show()
    slot.hide()
    slot.show()
    assert len(made) == 1 and slot.widget is made[0]
