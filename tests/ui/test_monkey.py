"""The app under a seeded monkey (tests/ui/monkey.py): random actions on a real drone image
measured by hand (the minke of tests/data/real) and on the sample project's video, checked
after each. DOLPHINFIT_MONKEY_SEED and DOLPHINFIT_MONKEY_STEPS replay or lengthen a run; a
failure prints its seed and the actions before it."""

import os
import shutil
from pathlib import Path

import pytest

from dolphinfit.core.project.sample import ensure_sample_project

from .monkey import Monkey, settle
from .test_app import measure_by_hand, open_and_wait

SEED = int(os.environ.get("DOLPHINFIT_MONKEY_SEED", "20261128"))
STEPS = int(os.environ.get("DOLPHINFIT_MONKEY_STEPS", "80"))
MINKE = Path(__file__).resolve().parents[1] / "data" / "real" / "minke" / "demo.JPG"


@pytest.mark.parametrize("media", ["minke", "sample"])
def test_random_actions_never_break_the_app(qtbot, qtlog, new_window, tmp_path, media):
    window = new_window()
    if media == "minke":
        still = tmp_path / "survey" / MINKE.name   # its project file is written beside it
        still.parent.mkdir()
        still.write_bytes(MINKE.read_bytes())
        open_and_wait(qtbot, window, still)
        measure_by_hand(qtbot, window)
    else:   # a copy: the monkey saves, and the cached sample must stay as it is
        sample = ensure_sample_project()
        copy = tmp_path / "sample"
        shutil.copytree(sample.parent, copy, ignore=shutil.ignore_patterns("*.autosave"))
        open_and_wait(qtbot, window, copy / sample.name)
    monkey = Monkey(window, SEED, tmp_path)
    seen = 0
    for _ in range(STEPS):
        with qtbot.captureExceptions() as exceptions:
            monkey.log.append(monkey.step())
            settle(qtbot)
        assert not exceptions, monkey.report(f"exception: {exceptions[0][1]!r}")
        messages = [record.message for record in qtlog.records[seen:]]
        seen = len(qtlog.records)
        monkey.check(messages)
    window.playback.stop()
    window.jobs.wait()
