"""The 3D fit in the app: the fit panel starts and cancels the current animal's fit in a
worker; a finished (or cancelled, partial) fit is saved in the animal's fit folder and recorded
in the project as an undoable edit; the current animal's fit is read back when shown, posed in
the 3D viewer at the current frame, and compared with the elliptical baseline."""

import threading
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from PySide6.QtCore import QObject, QPointF, Signal
from PySide6.QtGui import QColor, QPainterPath, QPen, QPolygonF
from PySide6.QtWidgets import QGraphicsPathItem

from dolphinfit.core.device import DEFAULT_DEVICE
from dolphinfit.core.errors import InputError
from dolphinfit.core.fit.motion import FramePose, ShownPose, shown_pose
from dolphinfit.core.fit.reporter import FitPreview
from dolphinfit.core.fit.result import STATUS_COMPLETE, STATUS_UNRELIABLE, FitResult
from dolphinfit.core.fit.result_io import read_fit_result
from dolphinfit.core.measure.stations import STATION_PCT
from dolphinfit.core.model.template import load_template
from dolphinfit.core.progress import Progress
from dolphinfit.core.project.calibrations import calibrated_clip_telemetry
from dolphinfit.core.project.fit_inputs import changed_since_fit, fit_inputs_of, stale_note
from dolphinfit.core.project.fit_overlay import silhouette_outlines
from dolphinfit.core.measure.hw_ratios import write_hw_csv
from dolphinfit.core.project.comparison_view import ComparisonView, comparison_view
from dolphinfit.core.project.fit_settings import FitSettings, fit_config, fit_dir, hw_table_path
from dolphinfit.core.project.mask_store import Coverage
from dolphinfit.core.project.model import Animal, with_animal
from dolphinfit.core.project.project_file import media_path, relative_media_path
from dolphinfit.core.project.results import FrameResult, frame_altitude, project_fit_config
from dolphinfit.ui.workers.background import BackgroundJobs
from dolphinfit.ui.widgets.canvas import FrameCanvas
from dolphinfit.ui.state.commands import push_edit
from dolphinfit.ui.widgets.fit_panel import FitPanel
from dolphinfit.ui.workers.fit_worker import FitJob, FitWorker
from dolphinfit.ui.widgets.lazy_widget import LazyWidget
from dolphinfit.ui.state.project_model import Change, ProjectModel
from dolphinfit.ui.widgets.results_panel import ResultsPanel
from dolphinfit.ui.state.viewer_state import ViewerState

if TYPE_CHECKING:
    from dolphinfit.ui.widgets.comparison_panel import ComparisonPanel
    from dolphinfit.ui.widgets.viewer3d import Viewer3D

SILHOUETTE_COLOUR = "#ff8c1a"  # orange: apart from the measuring handles and the water
SILHOUETTE_Z = 0.5             # above the frame, under the measuring overlay
TRACK_AGAIN = "track the animal again (Clip → Track the dolphin from a click, Ctrl+T)"


def _make_viewer() -> "Viewer3D":
    from dolphinfit.ui.widgets.viewer3d import (  # VTK: imported when the 3D view is first shown
        Viewer3D,
    )
    return Viewer3D()


def _make_comparison() -> "ComparisonPanel":
    from dolphinfit.ui.widgets.comparison_panel import ComparisonPanel  # matplotlib: on first show
    return ComparisonPanel()


def describe_fit(result: FitResult) -> str:
    """One line on a fit: its status in words, its mean IoU and figures, then its warnings."""
    head = ("3D fit complete" if result.status == STATUS_COMPLETE
            else f"⚠ 3D fit unreliable: {result.status_message}"
            if result.status == STATUS_UNRELIABLE
            else f"3D fit {result.status} (partial result): {result.status_message}")
    return (f"{head}. {len(result.frame_idx)} frames, mean IoU {float(result.iou.mean()):.3f}; "
            f"length {result.length_m:.3f} m, volume {result.volume_m3:.4f} m³, "
            f"mass {result.mass_kg:.1f} kg" + "".join(f"\n⚠ {w}" for w in result.warnings))


def mask_check(frames: np.ndarray, coverage: Coverage | None,
               has_masks: bool) -> tuple[str, bool]:
    """What the fit panel says of the masks of the fit's ``frames`` ((T,) int, in order) and
    whether the fit may start. A fit uses only frames whose mask is not empty and clear of
    the image border (core.fit.data.select_frames); ``coverage`` None (still being read)
    says nothing. Counting only: no mask is read."""
    if not has_masks:
        return (f"⚠ this clip has no masks: {TRACK_AGAIN} or choose them with Clip → Masks…",
                False)
    if coverage is None or len(frames) == 0:
        return "", True
    inside = frames[frames < coverage.num_frames]
    visible = coverage.visible[inside]
    num_usable = int(np.count_nonzero(visible & ~coverage.touches_border[inside]))
    span = f"frames {frames[0]}–{frames[-1]}"
    if num_usable == 0:
        border = int(np.count_nonzero(visible))
        why = f" ({border} touch the image border)" if border else ""
        return f"⚠ no usable masks in {span}{why}: {TRACK_AGAIN} or pick another range", False
    if num_usable < len(frames):
        return (f"{num_usable} of the {len(frames)} frames to fit ({span}) have a usable mask: "
                f"the fit uses only those; {TRACK_AGAIN} for the others", True)
    return "", True


class FitController(QObject):
    """Owns the fit panel, the 3D viewer, the comparison panel and the fit worker; draws the
    fitted silhouette on ``canvas`` and compares with the elliptical result ``results`` shows.
    ``fit_shown``: a fit is on show (the window then shows the 3D view);
    ``fit_frames_changed(frames)``: the frames the current animal's fit would use, for the
    timeline."""

    fit_shown = Signal()
    fit_frames_changed = Signal(object)

    def __init__(self, model: ProjectModel, state: ViewerState, jobs: BackgroundJobs,
                 canvas: FrameCanvas, results: ResultsPanel,
                 parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.model, self.state, self.jobs, self.results = model, state, jobs, results
        self.panel = FitPanel()
        self.viewer_slot = LazyWidget(_make_viewer, "The 3D view opens with the first fit.")
        self.comparison_slot = LazyWidget(_make_comparison, "No 3D fit of this animal yet.")
        self.viewer_slot.built.connect(self._on_viewer_built)
        self.comparison_slot.built.connect(self._on_comparison_built)
        self._view: ComparisonView | None = None   # what the comparison shows, once computed
        self._comparison_status = "No 3D fit of this animal yet."
        self.worker = FitWorker(self)
        self.device = DEFAULT_DEVICE   # where fits compute (Edit → Compute device; a preference)
        self._fits: dict[Path, FitResult] = {}   # fits read or made this session, by folder
        self._shown: Path | None = None          # the fit folder on show
        self._running: tuple | None = None  # clip index, animal ID, project path being fitted
        self._live: FitPreview | None = None     # the running fit's latest state
        self._silhouette_generation = 0
        self._closing = threading.Event()  # set on close: a fit cancelled then is not kept
        self._faces: np.ndarray | None = None
        self._coverage: Coverage | None = None  # the open clip's masks per frame
        self.panel.start_requested.connect(self.start)
        self.panel.range_typed.connect(self._check_masks)
        self.panel.cancel_requested.connect(self.worker.cancel)
        self.panel.settings_changed.connect(self._store_settings)
        self.worker.progress.connect(self._on_progress)
        self.worker.finished.connect(self._on_finished)
        self.worker.failed.connect(self._on_failed)
        self.worker.cancelled.connect(
            lambda: self._on_failed("cancelled before the first step: nothing to keep"))
        model.selection_changed.connect(self.refresh)
        # a measurement edit (every step of a drag) changes neither fit settings nor fits
        model.changed.connect(lambda change: None if change.kind == "measurement"
                              else self.refresh())
        state.frame_shown.connect(self._on_frame_shown)
        state.session_opened.connect(lambda _: self.refresh())
        results.result_shown.connect(self._on_elliptical)
        self.silhouette = QGraphicsPathItem()
        pen = QPen(QColor(SILHOUETTE_COLOUR), 1.5)
        pen.setCosmetic(True)
        self.silhouette.setPen(pen)
        self.silhouette.setZValue(SILHOUETTE_Z)
        self.silhouette.setVisible(False)
        canvas.scene().addItem(self.silhouette)
        self._silhouette_on = True

    # ----- the current animal
    def _animal(self) -> tuple[int, int, Animal] | None:
        m = self.model
        if m.clip_idx is None or m.animal_idx is None:
            return None
        return m.clip_idx, m.animal_idx, m.project.clips[m.clip_idx].animals[m.animal_idx]

    def _fit_folder(self, animal: Animal) -> Path | None:
        path = self.model.path
        if animal.fit_path is None or path is None:
            return None
        return (path.parent / animal.fit_path).resolve()

    def refresh(self) -> None:
        """Show the current animal's settings and fit (read back in the background)."""
        current = self._animal()
        self._check_masks()
        if current is None:
            self._show(None)
            return
        clip_idx, _, animal = current
        session = self.state.session_for(clip_idx)  # None: the animal's clip is still opening
        duration = None if session is None else session.source.clip.duration_s
        self.panel.set_settings(animal.fit_settings, duration)
        self._tick_fit_frames(animal.fit_settings)
        folder = self._fit_folder(animal)
        if folder is None or folder == self._shown:
            if folder is None:
                self._show(None)
            elif not self.worker.is_running:   # the clip's inputs may have changed since
                self._say_fit(folder)
                self._sync_comparison()
            return
        if folder in self._fits:
            self._show(folder)
            return
        self.jobs.run(lambda: read_fit_result(folder),
                      lambda result: self._read(folder, result),
                      lambda why: self.panel.show_status(f"⚠ saved fit not read: {why}"))

    def _tick_fit_frames(self, settings: FitSettings) -> None:
        """Mark on the timeline the frames a fit with ``settings`` would use."""
        if self.state.session_for(self.model.clip_idx) is not None:
            self.fit_frames_changed.emit(self._frames(settings))

    def set_coverage(self, coverage: Coverage | None) -> None:
        """The open clip's mask coverage changed (read, tracked, corrected): check again."""
        self._coverage = coverage
        self._check_masks()

    def _mask_check(self, settings: FitSettings | None = None) -> tuple[str, bool]:
        """``mask_check`` of the current animal's frames with ``settings`` (None: its own);
        nothing to say without an animal or while its clip is not the open one."""
        current = self._animal()
        if current is None or self.state.session_for(current[0]) is None:
            return "", True
        frames = self._frames(current[2].fit_settings if settings is None else settings)
        has_masks = self.model.project.clips[current[0]].masks_path is not None
        return mask_check(frames, self._coverage, has_masks)

    def _check_masks(self, settings: FitSettings | None = None) -> None:
        self.panel.show_mask_check(*self._mask_check(settings))

    def _frames(self, settings: FitSettings) -> np.ndarray:
        """The open clip's frames that a fit with ``settings`` uses."""
        media = self.state.session.source.clip
        return fit_config(settings).frames_of(media)

    def fit_frames(self) -> list[int]:
        """The open clip's frames that the current animal's fit uses (default settings when
        no animal of this clip is selected); a session must be open."""
        current = self._animal()
        own = current is not None and current[0] == self.state.session.clip_idx
        return self._frames(current[2].fit_settings if own else FitSettings()).tolist()

    def _read(self, folder: Path, result: FitResult) -> None:
        self._fits.setdefault(folder, result)  # a fit made meanwhile is newer than the file
        current = self._animal()
        if current is not None and self._fit_folder(current[2]) == folder:
            self._show(folder)

    @property
    def viewer(self) -> "Viewer3D | None":
        """The 3D view, once its dock has been shown."""
        return self.viewer_slot.widget

    @property
    def comparison(self) -> "ComparisonPanel | None":
        """The comparison panel, once its dock has been shown."""
        return self.comparison_slot.widget

    def _show(self, folder: Path | None) -> None:
        self._shown, self._view = folder, None
        if folder is None:
            self._update_silhouette(self.state.frame_idx)  # hides it, unless a fit runs
            self._comparison_status = "No 3D fit of this animal yet."
            if not self.worker.is_running:
                self.panel.show_status("Measure the animal, then fit the 3D model to the clip.")
        else:
            self._say_fit(folder)
            self._update_silhouette(self.state.frame_idx)
            self.fit_shown.emit()
            self._on_elliptical(self.results.current_result())
        self._sync_viewer()
        self._sync_comparison()

    def _say_fit(self, folder: Path) -> None:
        """The shown fit in words on the panel and above the comparison."""
        self._comparison_status = self._fit_status(folder)
        self.panel.show_status(self._comparison_status)

    def _fit_status(self, folder: Path) -> str:
        """The shown fit in words, first saying so where its clip's inputs changed since."""
        current = self._animal()
        changed = [] if current is None else changed_since_fit(
            self.model.project, self.model.project.clips[current[0]], current[2])
        return "\n".join(line for line in (stale_note(changed), describe_fit(self._fits[folder]))
                         if line)

    def _on_viewer_built(self, viewer: "Viewer3D") -> None:
        self._sync_viewer()

    def _on_comparison_built(self, panel: "ComparisonPanel") -> None:
        panel.hw_from_fit_requested.connect(self.use_fit_hw)
        self._sync_comparison()

    def _on_frame_shown(self, frame_idx: int) -> None:
        self._update_silhouette(frame_idx)

    def _sync_viewer(self) -> None:
        """Show the current fit (and the elliptical solid) in the 3D view, if it is built."""
        viewer = self.viewer
        if viewer is None:
            return
        if self._shown is None:
            viewer.clear()
            return
        result = self._fits[self._shown]
        viewer.set_fitted(result.faces, result.posed_verts, result.rest_verts)
        self._update_silhouette(self.state.frame_idx)
        if self._view is None:
            viewer.set_elliptical(None)
        else:
            viewer.set_elliptical(self._view.solid_verts, self._view.solid_faces)

    def _sync_comparison(self) -> None:
        """Show the comparison as computed, if the panel is built."""
        panel, view = self.comparison, self._view
        if panel is None:
            return
        panel.show_comparison(None if view is None else view.rows, self._comparison_status)
        if view is not None:
            panel.show_profiles(STATION_PCT, view.measured_widths_m, view.used_widths_m,
                                view.fitted_widths_m, view.hw_heights_m,
                                view.fitted_heights_m)

    # ----- the fitted silhouette over the frame
    def set_silhouette_visible(self, visible: bool) -> None:
        self._silhouette_on = visible
        self._update_silhouette(self.state.frame_idx)

    def _update_silhouette(self, frame_idx: int) -> None:
        """Pose the fit at ``frame_idx`` (core.fit.motion, worked out in the background): its
        outline over the frame where the fitted motion reaches it, and the saved fit's mesh
        in the 3D view, once that is built."""
        self._silhouette_generation += 1  # poses asked for before this one are stale
        session, saved, live = self.state.session, self._shown, self._live
        if live is not None and (self._running is None or session is None
                                 or self._running[0] != session.clip_idx):
            live = None  # the running fit is of another clip
        # while a fit runs its latest state is drawn, else the saved fit of the animal shown
        drawn = live if live is not None else None if saved is None else self._fits[saved]
        outline = None if drawn is None else self._outline_source(drawn, live is not None,
                                                                  frame_idx)
        if outline is None:
            self.silhouette.setVisible(False)
        viewed = None if saved is None or self.viewer is None else self._fits[saved]
        if outline is None and viewed is None:
            return
        shown = None if viewed is None else shown_pose(viewed.frame_idx, viewed.transl,
                                                       viewed.pose_aa, frame_idx)

        def pose() -> tuple[list[np.ndarray] | None, np.ndarray | None]:
            from dolphinfit.core.fit.pose_mesh import posed_mesh  # torch: off the GUI thread
            verts = None if shown is None else posed_mesh(viewed.rest_verts, viewed.betas,
                                                          shown.pose)
            if outline is None:
                return None, verts
            # the saved fit drawn over the frame is the one the 3D view shows: posed once
            at, draw = outline
            drawn_verts = (verts if drawn is viewed else
                           posed_mesh(drawn.rest_verts, drawn.betas, at))
            return draw(drawn_verts), verts

        self.jobs.run(pose, lambda posed, g=self._silhouette_generation: self._draw_pose(
            g, frame_idx, shown, *posed), lambda why: self.silhouette.setVisible(False))

    def _outline_source(self, source: "FitResult | FitPreview", is_live: bool,
                        frame_idx: int) -> tuple[FramePose,
                                                 Callable[[np.ndarray], list[np.ndarray]]] | None:
        """The pose of ``source`` at ``frame_idx`` and a function giving the outlines of its
        mesh so posed as the clip's camera saw it (run it off the GUI thread); None where none
        is drawn: the silhouette is off, the clip not open, no altitude, or the fitted motion
        does not reach the frame."""
        session = self.state.session
        if not self._silhouette_on or self.state.session_for(self.model.clip_idx) is None:
            return None
        shown = shown_pose(source.frame_idx, source.transl, source.pose_aa, frame_idx)
        if not shown.is_on_motion:
            return None
        try:
            altitude = frame_altitude(calibrated_clip_telemetry(
                self.model.project, session.clip_idx, session.telemetry), frame_idx)
        except InputError:
            return None
        faces = self._template_faces() if is_live else source.faces
        clip = self.model.project.clips[session.clip_idx]
        if clip.camera is None:
            return None
        intrinsics, lens = clip.camera.intrinsics(), clip.lens

        def outlines(verts: np.ndarray) -> list[np.ndarray]:   # the pinhole view, bent as
            drawn = silhouette_outlines(verts, faces, intrinsics, altitude)   # the lens saw it
            return drawn if lens is None else [lens.distort(line) for line in drawn]

        return shown.pose, outlines

    def _template_faces(self) -> np.ndarray:
        """The model's faces (every fit shares the template's), read once."""
        if self._faces is None:
            self._faces = load_template().faces
        return self._faces

    def _draw_pose(self, generation: int, frame_idx: int, shown: ShownPose | None,
                   outlines: list[np.ndarray] | None, verts: np.ndarray | None) -> None:
        if generation != self._silhouette_generation:
            return
        if verts is not None and self.viewer is not None:
            self.viewer.show_pose(frame_idx, verts, shown.label)
        if outlines is not None and self._silhouette_on:
            self._draw_silhouette(outlines)

    def _draw_silhouette(self, outlines: list[np.ndarray]) -> None:
        path = QPainterPath()
        for outline in outlines:
            path.addPolygon(QPolygonF([QPointF(u, v) for u, v in outline]))
            path.closeSubpath()
        self.silhouette.setPath(path)
        self.silhouette.setVisible(True)

    # ----- comparison
    def _on_elliptical(self, frame_result: FrameResult | None) -> None:
        """Compare once the elliptical result has its interval and a fit is shown."""
        if self._shown is None or frame_result is None or frame_result.estimate.interval is None:
            return
        m = self.model
        if (frame_result.key.clip, frame_result.key.animal) != (m.clip_idx, m.animal_idx):
            return  # the previous animal's result, still on show
        fit, folder = self._fits[self._shown], self._shown
        width = m.project.clips[frame_result.key.clip].known_camera().image_width_px
        self.jobs.run(lambda: comparison_view(frame_result.estimate, fit, width),
                      lambda view: self._show_comparison(folder, view),
                      lambda why: self._comparison_failed(folder, why))

    def _comparison_failed(self, folder: Path, why: str) -> None:
        if folder == self._shown:
            self._view, self._comparison_status = None, f"⚠ {why}"
            self._sync_comparison()

    def _show_comparison(self, folder: Path, view: ComparisonView) -> None:
        if folder != self._shown:
            return
        self._view, self._comparison_status = view, self._fit_status(folder)
        self._sync_comparison()
        self._sync_viewer()

    # ----- running a fit
    def _store_settings(self, settings: FitSettings) -> None:
        current = self._animal()
        if current is None or current[2].fit_settings == settings:
            return
        clip_idx, animal_idx, animal = current
        model = self.model
        push_edit(model, with_animal(model.project, clip_idx, animal_idx,
                                     replace(animal, fit_settings=settings)),
                  "fit settings", Change("clip", clip=clip_idx),
                  merge_tag=("fit settings", clip_idx, animal_idx))

    def start(self, settings: FitSettings) -> None:
        """Fit the current animal with ``settings`` (checked here, said in words if not)."""
        try:
            job = self._job(settings)
        except InputError as exc:
            self.panel.show_status(f"⚠ {exc}")
            return
        self._store_settings(settings)
        current = self._animal()
        if self.worker.start(job):
            clip_idx = current[0]
            self._running = (clip_idx, current[2].animal_id, self.model.path,
                             fit_inputs_of(self.model.project, self.model.project.clips[clip_idx]))
            self.panel.set_running(True)

    def _job(self, settings: FitSettings) -> FitJob:
        current = self._animal()
        if current is None:
            raise InputError("select an animal to fit (Clip → Add animal)")
        clip_idx, _, animal = current
        session, path = self.state.session_for(clip_idx), self.model.path
        if session is None:
            raise InputError("the clip is still opening")
        clip = self.model.project.clips[clip_idx]
        if clip.altitude != session.altitude:
            raise InputError("the altitude is being read again: start the fit in a moment")
        if session.telemetry is None:
            raise InputError(session.telemetry_error or "no altitude: Clip → Altitude…")
        note, can_start = self._mask_check(settings)
        if not can_start:
            raise InputError(note.removeprefix("⚠ "))
        return FitJob(discard=self._closing, media=media_path(path, clip),
                      telemetry=calibrated_clip_telemetry(self.model.project, clip_idx,
                                                          session.telemetry),
                      masks=(path.parent / clip.masks_path).resolve(),
                      camera=clip.known_camera(),
                      out_dir=fit_dir(path, clip.media_path, animal.animal_id),
                      config=project_fit_config(settings, self.model.project, path.parent),
                      lens=clip.lens, device=self.device)

    def _on_progress(self, progress: Progress) -> None:
        self.panel.show_progress(progress)
        if isinstance(progress.preview, FitPreview):
            self._live = progress.preview  # the running fit's state, drawn over the frame
            self._update_silhouette(self.state.frame_idx)

    def _on_failed(self, why: str) -> None:
        self._running, self._live = None, None
        self.panel.set_running(False)
        self._update_silhouette(self.state.frame_idx)
        self.panel.show_status(f"⚠ fit stopped: {why}")

    def _on_finished(self, outcome: tuple[FitResult, Path]) -> None:
        """Record the saved fit on its animal (found by ID: the tree may have changed)."""
        result, folder = outcome
        clip_idx, animal_id, project_path, inputs = self._running
        self._running, self._live = None, None
        self.panel.set_running(False)
        self._fits[folder.resolve()] = result
        model = self.model
        if model.path != project_path:
            self.panel.show_status(f"{describe_fit(result)} — saved in {folder}; its project "
                                   "is no longer open")
            return
        clips = model.project.clips
        animals = clips[clip_idx].animals if clip_idx < len(clips) else ()
        index = next((i for i, a in enumerate(animals) if a.animal_id == animal_id), None)
        if index is None:
            self.panel.show_status(f"{describe_fit(result)} — saved in {folder}, but its "
                                   "animal is gone from the project")
            return
        self._shown = None  # show it afresh
        push_edit(model, with_animal(model.project, clip_idx, index, replace(
            animals[index], fit_path=relative_media_path(model.path.parent, folder),
            fit_inputs=inputs)),
            f"3D fit of {animal_id}", Change("clip", clip=clip_idx))
        self.refresh()

    def use_fit_hw(self) -> None:
        """Save the shown fit's HW ratios beside the project and make them the project's
        (one undoable edit); the source names the fit, so results say where they came from."""
        current, folder, path = self._animal(), self._shown, self.model.path
        if current is None or folder is None or path is None:
            return
        clip = self.model.project.clips[current[0]]
        animal_id, fit = current[2].animal_id, self._fits[folder]
        table = hw_table_path(path, clip.media_path, animal_id)

        def make() -> str:
            from dolphinfit.core.model.hw_from_model import hw_from_mesh
            from dolphinfit.core.model.template import load_template
            hw = hw_from_mesh(fit.rest_verts, load_template().station_rings,
                              name=f"3D fit of {animal_id} ({clip.name})",
                              source=f"heights / widths of the fitted mesh at the stations, "
                                     f"{folder} ({fit.status})", is_provisional=False)
            write_hw_csv(table, hw)
            return relative_media_path(path.parent, table)

        def use(relative: str) -> None:
            model = self.model
            push_edit(model, replace(model.project, hw_ratios=relative),
                      f"HW ratios from the 3D fit of {animal_id}", Change("settings"))

        self.jobs.run(make, use, lambda why: self.panel.show_status(f"⚠ {why}"))

    def shown_fit(self) -> FitResult | None:
        """The current animal's fit on show, if any."""
        return None if self._shown is None else self._fits[self._shown]

    def shutdown(self) -> None:
        """Cancel a running fit (its partial state is not written) and wait for it; release
        the 3D view."""
        self._closing.set()
        self.worker.shutdown()
        if self.viewer is not None:
            self.viewer.close_viewer()
