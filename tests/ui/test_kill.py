"""The app killed with SIGKILL at random moments while it edits, saves, autosaves, imports
masks and fits (tests/ui/kill_child.py: the real window in a process of its own, started
again after each kill on what the last one left). After every kill:

- the project file opens and holds the last state saved, or the one being saved at the kill;
- an autosave left beside it opens and holds a state the project took;
- every masks file and fit folder the two name opens whole.

DOLPHINFIT_KILL_ROUNDS and DOLPHINFIT_KILL_MAX_S (the latest kill, seconds after the project
opened) lengthen the drill, DOLPHINFIT_KILL_SEED replays one; a failure names the round, the
seed and the child's last events."""

import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

from dolphinfit.core.fit.result_io import read_fit_result
from dolphinfit.core.io.masks import read_masks
from dolphinfit.core.io.video import open_clip
from dolphinfit.core.project.model import Project
from dolphinfit.core.project.project_file import autosave_path, read_project
from dolphinfit.core.project.sample import ensure_sample_project

from .kill_child import project_digest

ROUNDS = int(os.environ.get("DOLPHINFIT_KILL_ROUNDS", "2"))
SEED = int(os.environ.get("DOLPHINFIT_KILL_SEED", "20261128"))
CHILD = Path(__file__).with_name("kill_child.py")
READY_S = 90.0                  # a cold start of the app on a busy machine
KILL_AFTER_S = (0.1, float(os.environ.get("DOLPHINFIT_KILL_MAX_S", "3")))


def _events(log: Path) -> list[dict]:
    """The child's log; a line cut by the kill is left out."""
    events = []
    for line in log.read_text(encoding="utf-8").splitlines():
        try:
            events.append(json.loads(line))
        except json.JSONDecodeError:
            pass
    return events


def _file_states(events: list[dict]) -> set[str]:
    """The states the project file may hold: the last save finished, and one begun after."""
    saved = begun = None
    for event in events:
        if event["event"] == "save":
            begun = event["digest"]
        elif event["event"] == "saved":
            saved, begun = begun, None
    return {saved, begun} - {None}


def _held_states(events: list[dict]) -> set[str]:
    return {event["digest"] for event in events if "digest" in event}


def _check_whole(project: Project, folder: Path, where: str) -> None:
    """Every masks file and fit folder ``project`` names opens."""
    for clip in project.clips:
        if clip.masks_path is not None:
            read_masks(folder / clip.masks_path, open_clip(folder / clip.media_path))
        for animal in clip.animals:
            if animal.fit_path is not None:
                read_fit_result(folder / animal.fit_path)


def _under_way(life: list[dict]) -> list[str]:
    """What one life of the app was doing when it was killed: a save or autosave begun and
    not ended, a fit or mask import started and not finished, else its last action."""
    doing: dict[str, bool] = {}
    for event in life:
        kind = event["event"]
        if kind in ("save", "saved"):
            doing["save"] = kind == "save"
        elif kind == "autosave":
            doing["autosave"] = True
        elif kind == "did":
            doing["autosave"] = False
            if event["kind"] == "masks":
                doing["mask import"] = True
        elif kind == "fit_started":
            doing["fit"] = True
        elif kind in ("fit_done", "fit_failed"):
            doing["fit"] = False
        elif kind == "state" and event["edit"].startswith("masks from"):
            doing["mask import"] = False
    busy = [what for what, now in doing.items() if now]
    last = [e["kind"] for e in life if e["event"] == "did"]
    return busy or [f"after {last[-1]}" if last else "opening"]


def _wait_ready(log: Path, start: int, child: subprocess.Popen, where: str) -> None:
    """Until this life of the app (its events from ``start`` on) has opened the project."""
    deadline = time.monotonic() + READY_S
    while not any(e["event"] == "ready" for e in _events(log)[start:]):
        assert child.poll() is None, f"{where}: the app exited ({child.returncode}) unready"
        assert time.monotonic() < deadline, f"{where}: the app did not open in {READY_S} s"
        time.sleep(0.05)


def test_a_killed_app_never_leaves_a_broken_project(tmp_path):
    sample = ensure_sample_project()
    folder = tmp_path / "survey"
    shutil.copytree(sample.parent, folder, ignore=shutil.ignore_patterns("*.autosave"))
    project_path, log = folder / sample.name, tmp_path / "events.jsonl"
    initial = project_digest(read_project(project_path))
    log.write_text(json.dumps({"event": "save", "digest": initial}) + "\n"
                   + json.dumps({"event": "saved"}) + "\n")
    rng = random.Random(SEED)
    env = {**os.environ, "DOLPHINFIT_THREADS": "1", "OMP_NUM_THREADS": "1"}
    killed_during = Counter()
    for round_no in range(ROUNDS):
        where = f"kill round {round_no} (seed {SEED})"
        start = len(_events(log))
        child = subprocess.Popen([sys.executable, str(CHILD), str(project_path),
                                  str(rng.randrange(2**31)), str(log), str(folder / "masks")],
                                 env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        try:
            _wait_ready(log, start, child, where)
            time.sleep(rng.uniform(*KILL_AFTER_S))
            alive = child.poll() is None
        finally:
            child.send_signal(signal.SIGKILL)
            _, stderr = child.communicate()
        assert alive, f"{where}: the app exited by itself ({child.returncode})\n" \
                      f"{stderr.decode()[-2000:]}"
        events = _events(log)
        lives = events[start:]
        killed_during.update(_under_way(lives))
        trouble = [e for e in lives if e["event"] in ("exception", "error", "fit_failed")]
        assert not trouble, f"{where}: {trouble}\n{stderr.decode()[-2000:]}"
        saved = read_project(project_path)
        assert project_digest(saved) in _file_states(events), \
            f"{where}: {project_path.name} is neither the last saved state nor the one " \
            f"being saved; last events: {lives[-8:]}"
        _check_whole(saved, folder, where)
        autosave = autosave_path(project_path)
        if autosave.exists():
            kept = read_project(autosave)
            assert project_digest(kept) in _held_states(events), \
                f"{where}: the autosave holds a state the project never took"
            _check_whole(kept, folder, where)
        with log.open("a", encoding="utf-8") as stream:   # what the next life starts from
            stream.write("\n" + json.dumps({"event": "save", "digest": project_digest(saved)})
                         + "\n" + json.dumps({"event": "saved"}) + "\n")
    print(f"kill drill: {ROUNDS} rounds, killed during {dict(killed_during)}")
