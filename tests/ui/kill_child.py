"""One life of the real app for the kill drill (tests/ui/test_kill.py), run as a process of
its own: it opens PROJECT (restoring its autosave, as a user would after a crash), then does
project work at random from SEED until it is killed: edits, saves, autosaves, mask imports
and short fits, all through the window's own controllers. It logs to LOG, one JSON line each,
flushed at once, every state the project takes (with the edit that made it), what each save
and autosave is about to write, and when fits start and end, so that the drill knows which
states the files on disk may hold and what was under way at the kill.

  python kill_child.py PROJECT SEED LOG MASKS
"""

import hashlib
import json
import random
import sys
from pathlib import Path

from dolphinfit.core.project.fit_settings import FitSettings
from dolphinfit.core.project.model import Project
from dolphinfit.core.project.project_file import project_to_json

SHORT_FIT = FitSettings(start_s=0.0, end_s=0.4, fps=5.0, quality="quick")  # 2 frames
WORK = ("edit", "edit", "save", "autosave", "masks", "fit")


def project_digest(project: Project) -> str:
    """The project's content as it would be written, hashed."""
    text = json.dumps(project_to_json(project), sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()


def main(project_path: Path, seed: int, log_path: Path, masks: Path) -> int:
    from PySide6.QtCore import QTimer

    from dolphinfit.ui.app import application
    from dolphinfit.ui.main_window import MainWindow

    app = application()
    window = MainWindow()
    rng = random.Random(seed)
    log = log_path.open("a", encoding="utf-8")

    def note(event: str, **fields: object) -> None:
        log.write(json.dumps({"event": event, **fields}) + "\n")
        log.flush()

    ask, model = window.ask, window.model
    ask.restore_autosave = lambda path: True
    ask.save_changes = lambda: "save"
    ask.masks_source = lambda: masks
    ask.relink = lambda *asked: None
    ask.animal = lambda animal, others: (animal.animal_id, f"note {rng.randrange(10**6)}")
    ask.warn = lambda title, text: note("told", title=title, text=text)
    window.notifier.error = lambda title, text: note("error", title=title, text=text)
    model.changed.connect(lambda change: note("state", digest=project_digest(model.project),
                                              edit=model.undo_stack.undoText()))
    window.fits.worker.finished.connect(lambda result: note("fit_done"))
    window.fits.worker.failed.connect(lambda why: note("fit_failed", why=why))
    sys.excepthook = lambda kind, value, tb: note("exception", text=repr(value))

    def work() -> None:
        kind = rng.choice(WORK)
        if kind == "edit":
            window.actions_by_name["edit_animal"].trigger()
        elif kind == "save":
            note("save", digest=project_digest(model.project))
            window.actions_by_name["save"].trigger()
            note("saved")
        elif kind == "autosave":
            note("autosave", digest=project_digest(model.project), dirty=model.is_dirty)
            model.write_autosave()
        elif kind == "masks":
            window.on_masks()
        elif not window.fits.worker.is_running:
            window.fits.start(SHORT_FIT)
            note("fit_started")
        note("did", kind=kind)
        QTimer.singleShot(rng.randint(20, 300), work)

    def opened(*_: object) -> None:
        if not getattr(opened, "done", False):
            opened.done = True
            note("ready", digest=project_digest(model.project))
            QTimer.singleShot(0, work)

    window.state.session_opened.connect(opened)
    window.show()
    window.files.open_path(project_path)
    return app.exec()


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1]), int(sys.argv[2]), Path(sys.argv[3]), Path(sys.argv[4])))
