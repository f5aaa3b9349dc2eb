"""A seeded "monkey" for the app: random but valid user actions on a real window (menu items
and their shortcuts, clicks and wheel turns on the canvas, dialogs answered with random values
or cancelled, undo and redo runs, saves), and after every action the checks that no user can
break: no exception in a slot, no Qt warning of a deleted object or a cross-thread call, a
project that survives its own file. A failure names the seed and the actions up to it.

Tracking, scanning, fitting and opening other media are left out: they are tested on their own, and a
short run must stay short.
"""

import json
import random
from dataclasses import dataclass, field
from pathlib import Path

from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtWidgets import QApplication

from dolphinfit.core.measure.annotation import ALTITUDE_SOURCES
from dolphinfit.core.project.model import AltitudeSpec
from dolphinfit.core.project.project_file import project_from_json, project_to_json, read_project

LEFT = Qt.MouseButton.LeftButton
SKIPPED_ACTIONS = {  # opening media, quitting, tracking, scanning, fitting and slow exports
    "open", "open_folder", "add_media", "add_folder", "add_clips", "add_clip_folder",
    "scan_clip", "scan_all", "quit", "masks", "track_click",
    "retrack", "track_every_frame", "masks_network", "masks_colour", "masks_sam2",
    "export_meshes", "export_comparison", "export_project", "export_animal", "export_frame",
    "calibrate_altitude", "play"}
BAD_QT_MESSAGES = ("deleted", "different thread", "another thread", "QObject::")


@dataclass
class Monkey:
    """Plays ``steps`` random actions on ``window`` from ``seed``; ``log`` the actions done."""

    window: object
    seed: int
    folder: Path
    log: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.rng = random.Random(self.seed)
        self.saves = 0
        self._answer_questions()

    def _answer_questions(self) -> None:
        """Every dialog answered at random, as a user might, without showing it."""
        ask, rng = self.window.ask, self.rng
        ask.warn = lambda title, text: self.log.append(f"  (told: {title})")
        ask.show_shortcuts = ask.show_about = ask.show_manual = lambda: None
        ask.save_changes = lambda: "discard"
        ask.restore_autosave = lambda path: False
        ask.remove_animal = lambda animal: rng.random() < 0.5
        ask.frame_number = lambda current, last: rng.randint(0, last)
        ask.altitude = lambda *asked: (None if rng.random() < 0.3 else AltitudeSpec(
            constant_m=round(rng.uniform(8.0, 60.0), 2), source=rng.choice(ALTITUDE_SOURCES)))
        ask.animal = lambda animal, others: (None if rng.random() < 0.3
                                             else (f"dolphin {rng.randint(1, 99)}", "monkey"))
        ask.save_path = lambda current: self.folder / f"monkey_{self.saves}.dolphinfit"
        ask.videos_to_add = lambda: []
        ask.launch_height = lambda names: None
        ask.report = lambda title, text, details: self.log.append(f"  (told: {title})")
        for name in ("media_to_open", "media_to_add", "frames_folder", "export_dir",
                     "comparison_path", "mesh_export", "masks_source", "sam2_checkpoint",
                     "relink", "camera", "handle_style", "altitude_calibration", "lens_file"):
            setattr(ask, name, lambda *asked: None)

    def actions(self) -> list[str]:
        return sorted(name for name, action in self.window.actions_by_name.items()
                      if name not in SKIPPED_ACTIONS and action.isEnabled())

    def step(self) -> str:
        """One random action; its description."""
        kind = self.rng.choices(("action", "click", "wheel", "undo_run"), (6, 4, 1, 1))[0]
        window, canvas = self.window, self.window.canvas
        rect = canvas.image_rect()
        if kind == "action" or rect.width() <= 0:
            name = self.rng.choice(self.actions())
            if name == "save_as":
                self.saves += 1
            window.actions_by_name[name].trigger()
            return f"action {name}"
        if kind == "click":
            point = QPointF(self.rng.uniform(rect.left(), rect.right()),
                            self.rng.uniform(rect.top(), rect.bottom()))
            viewport_point: QPoint = canvas.mapFromScene(point)
            from PySide6.QtTest import QTest
            QTest.mouseClick(canvas.viewport(), LEFT, pos=viewport_point)
            return f"click ({point.x():.0f}, {point.y():.0f})"
        if kind == "wheel":
            canvas.zoom_by(self.rng.choice((0.8, 1.25)), QPointF(rect.center()))
            return "wheel"
        stack = window.model.undo_stack
        runs = self.rng.randint(1, 5)
        for _ in range(runs):
            (stack.undo if self.rng.random() < 0.6 else stack.redo)()
        return f"undo/redo ×{runs}"

    def check(self, qt_messages: list[str]) -> None:
        """The invariants after an action (AssertionError naming the seed and the actions)."""
        bad = [m for m in qt_messages if any(text in m for text in BAD_QT_MESSAGES)]
        assert not bad, self.report(f"Qt warned: {bad}")
        model = self.window.model
        doc = project_to_json(model.project)
        assert project_to_json(project_from_json(doc, "monkey")) == doc, \
            self.report("the project does not survive its own file")
        path = model.path
        if path is not None and path.exists() and not model.is_dirty:
            saved = project_to_json(read_project(path))
            assert json.dumps(saved, sort_keys=True) == json.dumps(doc, sort_keys=True), \
                self.report(f"{path.name} saved is not the project held")

    def report(self, what: str) -> str:
        return (f"monkey seed {self.seed}, after {len(self.log)} actions: {what}\n"
                + "\n".join(self.log[-40:]))


def settle(qtbot, ms: int = 10) -> None:
    """Let queued signals and worker results arrive."""
    QApplication.processEvents()
    qtbot.wait(ms)
