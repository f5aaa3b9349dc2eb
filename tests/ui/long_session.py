"""A long working session in the real app (issue 32 §3), to see whether it leaks: the main
window opens and closes CLIPS clips in turn (copies of the sample project, of its video with
its SRT as new media, and of the real minke still), measures FRAMES frames of the sample from
its masks, then runs FITS short 3D fits of it. After each step it samples the process (RSS,
open file descriptors, live widgets, live PySide wrappers, objects the garbage collector
tracks, threads) into a CSV, then prints each figure at the start, after each phase and at its
maximum, with its growth per step over the last half of each phase. (The window's QObjects
are not counted: ``findChildren`` makes the window's wrapper keep a wrapper of each child it
returns, after the child is deleted too, so counting them would grow what it counts.)

Growth that is the work, not a leak: each measured frame adds three undo steps and a row of
the project tree (4 wrappers) and, until every frame of the clip has been seen, a decoded
frame to the clip's cache (2.6 MiB at 720p, up to 512 MiB, dropped when the clip closes);
each fit adds an undo step. Undo steps and rows go when the project closes.

Not a pytest test (a run takes minutes); run it under a display:

  xvfb-run -a -s "-screen 0 1920x1200x24" .venv/bin/python tests/ui/long_session.py \\
      --clips 50 --frames 100 --fits 20 --out session.csv
"""

import argparse
import csv
import gc
import os
import shutil
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np

from app_waits import results_caught_up   # this script's folder (tests/ui) is on the path

MINKE = Path(__file__).resolve().parents[1] / "data" / "real" / "minke" / "demo.JPG"
WAIT_S = 120.0          # the longest any one step may take (a fit on two busy cores included)
FIT_WAIT_S = 600.0
SETTLE_MS = 150         # events turned between steps
SAVE_EVERY = 10         # measured frames between saves
# growth per step over the last half of a phase (and of its peak) above which a
# figure is flagged
FLAG_SLOPE = {"rss_mb": 0.2, "fds": 0.05, "widgets": 0.05, "wrappers": 0.5,
              "gc_objects": 200.0, "threads": 0.05, "os_threads": 0.05}


@dataclass(frozen=True)
class Sample:
    """The process after one step."""

    phase: str
    step: int
    seconds: float
    rss_mb: float
    fds: int
    widgets: int
    wrappers: int
    gc_objects: int
    threads: int
    os_threads: int


class Session:
    """The window, what it has been asked and told, and the samples taken."""

    def __init__(self) -> None:
        from dolphinfit.ui.app import application
        from dolphinfit.ui.main_window import MainWindow

        self.app = application()
        self.window = MainWindow(restore_layout=False)
        self.unexpected: list[str] = []   # questions and errors no step should meet
        self.counts = {"opened": 0, "shown": 0, "fit_done": 0, "fit_failed": 0}
        self.samples: list[Sample] = []
        self.started = time.monotonic()
        self._answer_questions()
        window = self.window
        window.state.session_opened.connect(lambda _: self._count("opened"))
        window.state.frame_shown.connect(lambda _: self._count("shown"))
        window.fits.worker.finished.connect(lambda _: self._count("fit_done"))
        window.fits.worker.failed.connect(lambda why: (self._count("fit_failed"),
                                                       self.unexpected.append(f"fit: {why}")))
        window.resize(1400, 900)
        window.show()

    def _count(self, name: str) -> None:
        self.counts[name] += 1

    def _answer_questions(self) -> None:
        """Every question gets a fixed answer, so that no dialog ever opens; one that no
        step should ask is noted (and answered as a cancel)."""
        from dolphinfit.core.project.model import AltitudeSpec
        from dolphinfit.core.project.project_file import relative_media_path
        from dolphinfit.ui.dialogs.questions import Questions

        ask = self.window.ask
        for name in dir(Questions):
            if not name.startswith("_") and callable(getattr(Questions, name)):
                setattr(ask, name, lambda *asked, name=name: self.unexpected.append(
                    f"asked {name}{asked!r}"))

        def altitude(media: Path, project_dir: Path, clip: object,
                     current: AltitudeSpec | None) -> AltitudeSpec:
            """The SRT beside a video, as the dialog offers it; a still's constant 20 m."""
            srt = media.with_suffix(".SRT")
            if srt.exists():
                return AltitudeSpec(path=relative_media_path(project_dir, srt),
                                    launch_height_m=1.5, source="barometer")
            return AltitudeSpec(constant_m=20.0, source="laser")

        ask.altitude = altitude
        ask.restore_autosave = lambda path: False
        ask.save_changes = lambda: "discard"
        ask.media_changed = lambda names: True
        ask.warn = lambda title, text: self.unexpected.append(f"warned {title}: {text}")

    # ----- waiting
    def turn(self, ms: int = SETTLE_MS) -> None:
        """Run the event loop for ``ms``, deferred deletions included (as ``exec`` does)."""
        from PySide6.QtCore import QCoreApplication, QEvent, QEventLoop, QTimer

        loop = QEventLoop()
        QTimer.singleShot(ms, loop.quit)
        loop.exec()
        QCoreApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete)

    def wait_until(self, ready: Callable[[], bool], what: str, timeout_s: float = WAIT_S) -> None:
        deadline = time.monotonic() + timeout_s
        while not ready():
            if time.monotonic() > deadline:
                raise TimeoutError(f"waited {timeout_s:.0f} s for {what}; "
                                   f"unexpected: {self.unexpected[-3:]}")
            self.turn(20)

    def settle(self) -> None:
        """Background jobs done and their results delivered, then a little more."""
        for _ in range(3):
            self.window.jobs.wait(int(WAIT_S * 1000))
            self.turn()

    # ----- sampling
    def sample(self, phase: str, step: int) -> Sample:
        import psutil
        import shiboken6
        from PySide6.QtWidgets import QApplication

        gc.collect()
        process = psutil.Process()
        taken = Sample(phase, step, round(time.monotonic() - self.started, 2),
                       round(process.memory_info().rss / 2**20, 1), process.num_fds(),
                       len(QApplication.allWidgets()),
                       len(shiboken6.Shiboken.getAllValidWrappers()),
                       len(gc.get_objects()), threading.active_count(),
                       process.num_threads())
        self.samples.append(taken)
        return taken

    # ----- the user's steps
    def open(self, path: Path) -> None:
        """Open a project or media, closing what was open; wait for its first frame, its
        altitude read and its results."""
        window, opened, shown = self.window, self.counts["opened"], self.counts["shown"]
        window.files.open_path(path)
        self.wait_until(lambda: self.counts["opened"] > opened, f"{path.name} to open")

        def ready() -> bool:
            session = window.state.session
            clip = window.model.project.clips[window.model.clip_idx]
            return (self.counts["shown"] > shown and session is not None
                    and session.altitude == clip.altitude and clip.altitude is not None)

        self.wait_until(ready, f"{path.name}'s first frame and altitude")
        self.settle()

    def measure(self, frame_idx: int, mask: np.ndarray) -> None:
        """Measure ``frame_idx`` as tests/ui/test_app_fit.py does: the length from the mask's
        midline, the widths suggested from the mask; wait for its result with its interval."""
        from dolphinfit.core.errors import InputError
        from dolphinfit.core.measure.mask_midline import midline_from_mask
        from dolphinfit.ui.state.commands import edit_measurement

        window, model = self.window, self.window.model
        if window.state.frame_idx != frame_idx:
            shown = self.counts["shown"]
            window.go_to_frame(frame_idx)
            self.wait_until(lambda: self.counts["shown"] > shown, f"frame {frame_idx}")
        window.on_measure_frame()
        key = model.current_key()
        edit_measurement(model, key, replace(model.current_measurement(),
                                             midline_px=midline_from_mask(mask)), "length")
        try:
            window.overlay.suggest_edges(mask)
        except InputError as exc:
            self.unexpected.append(f"frame {frame_idx}: edges not suggested: {exc}")
        self.wait_until(lambda: results_caught_up(window), f"frame {frame_idx}'s result")
        self.settle()

    def fit(self) -> None:
        """A short fit of the current animal (2 frames, quick) to its end, shown."""
        from dolphinfit.core.project.fit_settings import FitSettings

        done = self.counts["fit_done"] + self.counts["fit_failed"]
        self.window.fits.start(FitSettings(start_s=0.0, end_s=0.4, fps=5.0, quality="quick"))
        self.wait_until(lambda: self.counts["fit_done"] + self.counts["fit_failed"] > done,
                        "the fit", FIT_WAIT_S)
        self.wait_until(lambda: self.window.fits.shown_fit() is not None, "the fit shown")
        self.settle()
        self.window.files.save()
        self.settle()


def sample_copy(sample: Path, folder: Path) -> Path:
    """The sample project copied into ``folder`` (its autosave left behind)."""
    shutil.copytree(sample.parent, folder, ignore=shutil.ignore_patterns("*.autosave"))
    return folder / sample.name


def clip_paths(sample: Path, work: Path, count: int) -> list[Path]:
    """``count`` things to open in turn, each in its own folder: the sample project, its
    video as new media with its SRT beside it, the minke still."""
    video = sample.parent / "clip.mp4"
    paths = []
    for idx in range(count):
        folder = work / "clips" / f"{idx:03d}"
        kind = idx % 3
        if kind == 0:
            paths.append(sample_copy(sample, folder))
            continue
        folder.mkdir(parents=True)
        if kind == 1:
            target = folder / f"DJI_{idx:04d}.MP4"
            shutil.copyfile(video, target)
            shutil.copyfile(video.with_suffix(".SRT"), target.with_suffix(".SRT"))
        else:
            target = folder / f"minke_{idx:03d}.JPG"
            shutil.copyfile(MINKE, target)
        paths.append(target)
    return paths


def slope(samples: list[Sample], name: str, peak: bool = False) -> float:
    """Growth of ``name`` per step over the last half of the samples (least squares); with
    ``peak``, of its highest value so far (which a figure that swings within bounds stops
    raising)."""
    values = np.array([getattr(s, name) for s in samples], dtype=float)
    if peak:
        values = np.maximum.accumulate(values)
    half = len(samples) // 2
    if len(samples) - half < 2:
        return float("nan")
    return float(np.polyfit([s.step for s in samples[half:]], values[half:], 1)[0])


def report(samples: list[Sample], phases: list[str]) -> list[str]:
    """The table: each figure at the start, after each phase, its maximum and its growth per
    step over the last half of each phase; flagged where both that growth and the growth of
    its peak pass FLAG_SLOPE."""
    names = [f.name for f in fields(Sample)][3:]
    by_phase = {p: [s for s in samples if s.phase == p] for p in phases}
    head = (["figure", "start"] + [f"after {p}" for p in phases] + ["max"]
            + [f"/{p[:-1] if p.endswith('s') else p}" for p in phases] + ["flag"])
    rows = [head]
    flagged = []
    for name in names:
        slopes = {p: slope(by_phase[p], name) for p in phases}
        growing = [p for p, rate in slopes.items() if rate > FLAG_SLOPE[name]
                   and slope(by_phase[p], name, peak=True) > FLAG_SLOPE[name]]
        flagged += [f"{name} grows {slopes[p]:+.2f} per step in {p}" for p in growing]
        rows.append([name, f"{getattr(samples[0], name):g}"]
                    + [f"{getattr(by_phase[p][-1], name):g}" for p in phases]
                    + [f"{max(getattr(s, name) for s in samples):g}"]
                    + [f"{slopes[p]:+.2f}" for p in phases]
                    + ["GROWS: " + ", ".join(growing) if growing else "flat"])
    widths = [max(len(row[i]) for row in rows) for i in range(len(head))]
    lines = ["  ".join(cell.rjust(w) for cell, w in zip(row, widths)) for row in rows]
    return lines + (flagged or ["no figure grows past its flag over the last half of a phase"])


def run(clips: int, frames: int, fits: int, out: Path, work: Path) -> int:
    from dolphinfit.core.io.masks import read_masks
    from dolphinfit.core.project.sample import ensure_sample_project

    sample = ensure_sample_project()
    paths = clip_paths(sample, work, clips)
    session = Session()
    writer_file = out.open("w", newline="", encoding="utf-8")
    writer = csv.writer(writer_file)
    writer.writerow([f.name for f in fields(Sample)])
    phases, seconds = [], {}

    def note(phase: str, step: int) -> None:
        taken = session.sample(phase, step)
        writer.writerow([getattr(taken, f.name) for f in fields(Sample)])
        writer_file.flush()
        if step % 10 == 0:
            print(f"{phase} {step}: {taken}", flush=True)

    session.turn(500)
    note("start", 0)
    phase_started = time.monotonic()
    for idx, path in enumerate(paths, 1):
        session.open(path)
        note("clips", idx)
    if clips:
        phases.append("clips")
        seconds["clips"] = time.monotonic() - phase_started

    project = sample_copy(sample, work / "measured")
    session.open(project)
    window = session.window
    clip = window.model.project.clips[0]
    masks = read_masks(project.parent / clip.masks_path)
    visible = np.flatnonzero(masks.is_visible)
    note("frames", 0)
    phase_started = time.monotonic()
    for idx in range(frames):
        turn, position = divmod(idx, len(visible))
        if position == 0 and turn > 0:   # every visible frame measured: the next animal's
            window.animals.add_animal()
            session.settle()
        session.measure(int(visible[position]), masks.mask(int(visible[position])))
        if (idx + 1) % SAVE_EVERY == 0:
            window.files.save()
        note("frames", idx + 1)
    if frames:
        phases.append("frames")
        seconds["frames"] = time.monotonic() - phase_started

    phase_started = time.monotonic()
    for idx in range(fits):
        session.fit()
        note("fits", idx + 1)
    if fits:
        phases.append("fits")
        seconds["fits"] = time.monotonic() - phase_started

    window.shutdown()
    writer_file.close()
    for line in report(session.samples, phases):
        print(line)
    steps = {"clips": clips, "frames": frames, "fits": fits}
    print("wall time: " + ", ".join(f"{p} {seconds[p]:.0f} s ({seconds[p] / steps[p]:.2f} s/step)"
                                    for p in phases))
    if session.unexpected:
        print(f"{len(session.unexpected)} unexpected questions or errors, first: "
              + "; ".join(session.unexpected[:5]))
    return 1 if session.unexpected else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clips", type=int, default=50)
    parser.add_argument("--frames", type=int, default=100)
    parser.add_argument("--fits", type=int, default=20)
    parser.add_argument("--out", type=Path, default=Path("long_session.csv"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="dolphinfit-long-session-") as work:
        # the user's config (recent projects, preferences) is a temporary one
        os.environ["DOLPHINFIT_CONFIG_DIR"] = str(Path(work) / "config")
        return run(args.clips, args.frames, args.fits, args.out.resolve(), Path(work))


if __name__ == "__main__":
    sys.exit(main())
