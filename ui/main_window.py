"""The main window: wires the canvas, timeline, measuring overlay, project tree and results
panel to the project model, and turns each menu action (resources/ui/actions.json) into a
command. Its questions to the user are asked through ``self.ask`` (ui.dialogs.questions),
apart from the changes they lead to; errors reach the user through the notifier. Opening and
saving are ``self.files`` (ui.controllers.project_files), exports ``self.exports``."""

from collections import deque
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path

import numpy as np
from PySide6.QtCore import QByteArray, Qt
from PySide6.QtGui import QAction, QActionGroup, QCloseEvent, QKeySequence
from PySide6.QtWidgets import (
    QDockWidget,
    QLabel,
    QMainWindow,
    QMenu,
    QVBoxLayout,
    QWidget,
)

from dolphinfit.core.camera_presets import CameraPreset, preset_resolution_mismatch
from dolphinfit.core.device import AUTO, CUDA, DEFAULT_DEVICE, DEVICES, cuda_available
from dolphinfit.core.errors import InputError
from dolphinfit.core.project.model import CAMERA_UNKNOWN
from dolphinfit.core.project.recent import recent_projects
from dolphinfit.core.segment.backends import BACKENDS, COLOUR, DEFAULT_BACKEND, NETWORK, SAM2
from dolphinfit.core.segment.sam2_backend import INSTALL_HINT, PACKAGE, installed
from dolphinfit.ui.action_table import load_action_table
from dolphinfit.ui.app import APP_NAME
from dolphinfit.ui.workers.background import BackgroundJobs
from dolphinfit.ui.widgets.canvas import FrameCanvas
from dolphinfit.ui.state.clip_session import ClipSession
from dolphinfit.ui.dialogs.questions import Questions
from dolphinfit.ui.controllers.animal_commands import AnimalCommands
from dolphinfit.ui.controllers.clip_intake_controller import ClipIntakeController
from dolphinfit.ui.controllers.clip_sessions import ClipSessions
from dolphinfit.ui.controllers.export_controller import ExportController
from dolphinfit.ui.controllers.fit_controller import FitController
from dolphinfit.ui.controllers.project_files import ProjectFiles
from dolphinfit.ui.controllers.scan_controller import ScanController
from dolphinfit.ui.workers.frame_loader import FrameLoader
from dolphinfit.ui.state.handle_style import HandleStyle
from dolphinfit.ui.controllers.mask_controller import MaskController
from dolphinfit.ui.widgets.measure_overlay import (
    COARSE_NUDGE_PX, FINE_NUDGE_PX, NUDGE_PX, MeasureOverlay,
)
from dolphinfit.ui.controllers.playback import Playback
from dolphinfit.ui.state.preferences import load_preferences, save_preference
from dolphinfit.ui.state.project_model import Change, ProjectModel
from dolphinfit.ui.widgets.frame_picker import THUMBNAIL_PX, FramePicker
from dolphinfit.ui.widgets.project_panel import ProjectPanel
from dolphinfit.ui.widgets.results_panel import ResultsPanel
from dolphinfit.ui.widgets.timeline import Timeline
from dolphinfit.ui.state.viewer_state import Notifier, ViewerState, selected_clip

LAYOUT_PREFERENCE = "window_layout"   # size, place and docks when last closed
LAYOUT_VERSION = 3                     # of the dock layout: a new one ignores older layouts
RECENT_ACTIONS = 40                    # the last actions a crash report names
NUDGE_ACTIONS = {  # action → (direction, image px): outward +1, inward −1
    "nudge_out": (+1, NUDGE_PX), "nudge_in": (-1, NUDGE_PX),
    "nudge_out_fine": (+1, FINE_NUDGE_PX), "nudge_in_fine": (-1, FINE_NUDGE_PX),
    "nudge_out_coarse": (+1, COARSE_NUDGE_PX), "nudge_in_coarse": (-1, COARSE_NUDGE_PX)}
STEP_ACTIONS = {"next_frame": 1, "previous_frame": -1, "next_10": 10, "previous_10": -10,
                "next_100": 100, "previous_100": -100}
MIRROR_ACTIONS = {"mirror_none": None, "mirror_a": "A", "mirror_b": "B"}
MASK_TOOL_ACTIONS = {"mask_tool_off": None, "mask_brush": "brush", "mask_eraser": "eraser"}
BACKEND_ACTIONS = {"masks_network": NETWORK, "masks_colour": COLOUR, "masks_sam2": SAM2}
DEVICE_ACTIONS = {f"device_{device}": device for device in DEVICES}   # core.device's names
CUDA_CHECKING = "asking torch whether it sees a CUDA GPU…"
NO_CUDA = ("torch sees no CUDA GPU here (the CPU-only build of torch, or no GPU or driver): "
           "Help → Manual → Install tells how to install a CUDA build")


def _gsd_text(camera: CameraPreset | None, preset_name: str | None, altitude_m: float) -> str:
    """The status bar's GSD at ``altitude_m``, with where a camera of no preset came from
    (a photo's EXIF, values typed)."""
    if camera is None:
        return f"GSD: {CAMERA_UNKNOWN}"
    gsd_cm = 100 * camera.intrinsics().gsd_m_per_px(altitude_m)
    return f"GSD {gsd_cm:.2f} cm/px" + ("" if preset_name else f" ({camera.description})")


class MainWindow(QMainWindow):
    """The app's window: it builds the views, docks, menus and controllers, and wires them
    to the project model, the viewer state (the open clip, the frame on screen) and the
    notifier."""

    def __init__(self, restore_layout: bool = True) -> None:
        """``restore_layout``: open at the size, place and dock layout the window had when
        last closed (not for the README's screenshots)."""
        super().__init__()
        self.model = ProjectModel(parent=self)
        self.recent_actions: deque[str] = deque(maxlen=RECENT_ACTIONS)  # for crash reports
        self.jobs = BackgroundJobs(self)
        self.probe = BackgroundJobs(self)  # its own pool: a slow CUDA driver delays no clip
        self.state = ViewerState(self)
        self.notifier = Notifier(self)
        self.ask = Questions(self)
        self.files = ProjectFiles(self.model, self.ask, self.notifier, self.jobs, parent=self)
        self.sessions = ClipSessions(self.model, self.state, self.ask, self.notifier, self.jobs,
                                     parent=self)
        self.animals = AnimalCommands(self.model, self.state, self.ask, self.notifier,
                                      parent=self)
        self._pending_frame: int | None = None

        self.canvas = FrameCanvas()
        self.timeline = Timeline()
        self.loader = FrameLoader(self)
        self.playback = Playback(self)
        self.overlay = MeasureOverlay(self.canvas, self.model)
        self.results = ResultsPanel(self.model)
        self.results.set_altitude_lookup(self.sessions.altitude_at)
        self.project_panel = ProjectPanel(self.model)
        self.fits = FitController(self.model, self.state, self.jobs, self.canvas, self.results,
                                  parent=self)
        self.masks = MaskController(self.model, self.state, self.notifier, self.jobs,
                                    self.canvas, self.fits.fit_frames, parent=self)
        self.exports = ExportController(self.model, self.notifier, self.ask,
                                        self.fits.shown_fit, parent=self)
        self.scans = ScanController(self.model, self.notifier, self.jobs, parent=self)
        self.intake = ClipIntakeController(self.model, self.files, self.ask, self.notifier, self)
        self.picker = FramePicker()
        self._build_layout()
        self.actions_by_name = self._build_menus()
        self._apply_preferences()
        self.probe.run(cuda_available, self._on_cuda_probed,
                       lambda why: self._on_cuda_probed(False))
        self._connect()
        self._update_title()
        self.resize(1280, 900)
        self.layout_restored = restore_layout and self._restore_layout()

    # ------------------------------------------------------------------ building
    def _build_layout(self) -> None:
        central = QWidget()
        layout = QVBoxLayout(central)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(2)
        layout.addWidget(self.canvas, stretch=1)
        layout.addWidget(self.timeline)
        self.setCentralWidget(central)
        docks = {}
        for title, widget, area in (
                ("Project", self.project_panel, Qt.LeftDockWidgetArea),
                ("Frames", self.picker, Qt.LeftDockWidgetArea),
                ("3D fit", self.fits.panel, Qt.LeftDockWidgetArea),
                ("Results", self.results, Qt.RightDockWidgetArea),
                ("Comparison", self.fits.comparison_slot, Qt.RightDockWidgetArea),
                ("3D view", self.fits.viewer_slot, Qt.RightDockWidgetArea)):
            dock = QDockWidget(title, self)
            dock.setObjectName(title)
            dock.setWidget(widget)
            dock.setFeatures(QDockWidget.DockWidgetMovable | QDockWidget.DockWidgetFloatable)
            self.addDockWidget(area, dock)
            docks[title] = dock
        self.tabifyDockWidget(docks["Results"], docks["Comparison"])
        self.tabifyDockWidget(docks["Comparison"], docks["3D view"])
        self.tabifyDockWidget(docks["Frames"], docks["3D fit"])
        docks["Results"].raise_()
        docks["Frames"].raise_()
        docks["3D view"].hide()  # its tab comes with the first fit: VTK loads only then
        self.fits.fit_shown.connect(self._show_3d_view)
        self.resizeDocks([docks["Project"]], [300], Qt.Horizontal)
        self.resizeDocks([docks["Results"]], [400], Qt.Horizontal)
        self.docks = docks
        self.status_label = QLabel()
        self.cursor_label = QLabel()
        self.camera_warning = QLabel()
        self.camera_warning.setStyleSheet("color: #c00000; font-weight: bold")
        for label in (self.camera_warning, self.cursor_label, self.status_label):
            self.statusBar().addPermanentWidget(label)

    def _show_3d_view(self) -> None:
        """Add the 3D view's tab to the results' and the comparison's, not in front: the video
        keeps its size and the results stay in sight while measuring."""
        self.docks["3D view"].show()

    def _build_menus(self) -> dict[str, QAction]:
        menus, specs = load_action_table()
        bar = {name: self.menuBar().addMenu(f"&{name}") for name in menus}
        submenus: dict[tuple[str, str], QMenu] = {}
        actions: dict[str, QAction] = {}
        mirror_group = QActionGroup(self)
        mode_group = QActionGroup(self)
        tool_group = QActionGroup(self)
        backend_group = QActionGroup(self)
        device_group = QActionGroup(self)
        for spec in specs:
            action = QAction(spec.label, self)
            action.setObjectName(spec.name)
            if spec.shortcut:
                action.setShortcut(QKeySequence(spec.shortcut))
            if spec.scope == "canvas":
                action.setShortcutContext(Qt.ShortcutContext.WidgetWithChildrenShortcut)
                self.canvas.addAction(action)
            action.setCheckable(spec.checkable)
            action.triggered.connect(lambda *_, name=spec.name: self.recent_actions.append(name))
            action.triggered.connect(self._handler(spec.name))
            if spec.name in MIRROR_ACTIONS:
                mirror_group.addAction(action)
            if spec.name in ("length_mode", "widths_mode"):
                mode_group.addAction(action)
            if spec.name in MASK_TOOL_ACTIONS:
                tool_group.addAction(action)
            if spec.name in BACKEND_ACTIONS:
                backend_group.addAction(action)
            if spec.name in DEVICE_ACTIONS:
                device_group.addAction(action)
            menu = bar[spec.menu]
            if spec.submenu:
                if (spec.menu, spec.submenu) not in submenus:
                    submenus[spec.menu, spec.submenu] = menu.addMenu(spec.submenu)
                    submenus[spec.menu, spec.submenu].setToolTipsVisible(True)
                menu = submenus[spec.menu, spec.submenu]
            menu.addAction(action)
            if spec.name == "open":
                self.recent_menu = bar[spec.menu].addMenu("Open recent")
                self.recent_menu.aboutToShow.connect(self._fill_recent_menu)
            actions[spec.name] = action
        toolbar = self.addToolBar("Measure")
        toolbar.setObjectName("measure-toolbar")
        for name in ("measure_frame", "length_mode", "widths_mode", "reverse", "skip_station",
                     "suggest_edges", "fit_view"):
            toolbar.addAction(actions[name])
        if not installed():
            actions["masks_sam2"].setEnabled(False)
            actions["masks_sam2"].setToolTip(f"needs the '{PACKAGE}' package: {INSTALL_HINT}")
        actions["device_cuda"].setEnabled(False)   # until the probe answers
        actions["device_cuda"].setToolTip(CUDA_CHECKING)
        for menu in ("Clip", "Edit"):
            bar[menu].setToolTipsVisible(True)
        actions["mirror_none"].setChecked(True)
        actions["fit_silhouette"].setChecked(True)
        actions["show_masks"].setChecked(True)
        actions["mask_tool_off"].setChecked(True)
        actions["length_mode"].setChecked(True)
        return actions

    def _handler(self, name: str) -> Callable[..., None]:
        """What an action does: a frame step, a mirror side, a nudge, or ``on_<name>``."""
        if name in STEP_ACTIONS:
            return lambda *_: self._step(STEP_ACTIONS[name])
        if name in MIRROR_ACTIONS:
            return lambda *_: self.overlay.set_mirror_side(MIRROR_ACTIONS[name])
        if name in NUDGE_ACTIONS:
            return lambda *_: self.overlay.nudge(*NUDGE_ACTIONS[name])
        if name in MASK_TOOL_ACTIONS:
            return lambda *_: self.masks.set_tool(MASK_TOOL_ACTIONS[name])
        if name in BACKEND_ACTIONS:
            return lambda *_: self._choose_mask_backend(BACKEND_ACTIONS[name])
        if name in DEVICE_ACTIONS:
            return lambda *_: self._set_device(DEVICE_ACTIONS[name])
        return getattr(self, f"on_{name}")

    def _connect(self) -> None:
        self.notifier.error_raised.connect(self._show_error)
        self.notifier.status_shown.connect(self.statusBar().showMessage)
        self.fits.fit_frames_changed.connect(self.timeline.set_fit_frames)
        self.masks.coverage_changed.connect(self.timeline.set_coverage)
        self.masks.coverage_changed.connect(self.fits.set_coverage)
        self.files.session_closing.connect(self.sessions.close)
        self.files.clip_chosen.connect(self.sessions.open_current)
        self.intake.clip_chosen.connect(self.sessions.open_current)
        self.sessions.opened.connect(self._on_session_opened)
        self.sessions.telemetry_changed.connect(self._on_telemetry_changed)
        self.state.session_closed.connect(self._on_session_closed)
        self.masks.seeding.connect(
            lambda on: self.overlay.set_frame(None if on else self.state.frame_idx))
        m = self.model
        m.changed.connect(self._on_model_changed)
        m.selection_changed.connect(self._on_selection_changed)
        m.dirty_changed.connect(lambda _: self._update_title())
        m.path_changed.connect(self._update_title)
        m.autosave_failed.connect(lambda why: self.notifier.status(f"autosave failed: {why}",
                                                                    10_000))
        self.timeline.frame_requested.connect(self._seek)
        self.playback.frame_requested.connect(self.go_to_frame)
        self.loader.frame_ready.connect(self._on_frame_ready)
        self.loader.failed.connect(self._on_frame_failed)
        self.canvas.cursor_moved.connect(self._on_cursor_moved)
        self.canvas.space_tapped.connect(self.on_play)
        self.overlay.status_message.connect(lambda text: self.notifier.status(text, 5000))
        self.results.animal_figures.connect(self.project_panel.set_figures)
        self.scans.statuses_changed.connect(self.project_panel.set_statuses)
        self.scans.scan_shown.connect(self._show_scan)
        self.picker.frame_chosen.connect(self._measure_scanned_frame)
        self.picker.reject_toggled.connect(
            lambda animal, frame: self.scans.toggle_rejected(self.model.clip_idx, animal, frame))
        self.picker.thumbnails_wanted.connect(self._fetch_thumbnails)

    def _apply_preferences(self) -> None:
        prefs = load_preferences()
        if isinstance(prefs.get("handle_style"), dict):
            try:
                self.overlay.set_style(HandleStyle(**prefs["handle_style"]))
            except (TypeError, ValueError):
                pass  # a hand-edited preferences file: keep the default style
        auto_zoom = bool(prefs.get("auto_zoom", False))
        self.actions_by_name["auto_zoom"].setChecked(auto_zoom)
        self.overlay.auto_zoom = auto_zoom
        checkpoint = prefs.get("sam2_checkpoint")
        if isinstance(checkpoint, str) and Path(checkpoint).is_file():
            self.masks.sam2_checkpoint = Path(checkpoint)
        backend = prefs.get("mask_backend", DEFAULT_BACKEND)
        usable = backend in BACKENDS and (backend != SAM2 or (
            installed() and self.masks.sam2_checkpoint is not None))
        self._set_mask_backend(backend if usable else DEFAULT_BACKEND, save=False)
        device = prefs.get("compute_device", DEFAULT_DEVICE)
        self._set_device(device if device in DEVICES else DEFAULT_DEVICE, save=False)

    def _choose_mask_backend(self, backend: str) -> None:
        """The Clip menu's choice; SAM-2 asks for its checkpoint while it has none."""
        checkpoint = self.masks.sam2_checkpoint
        if backend == SAM2 and (checkpoint is None or not checkpoint.is_file()):
            checkpoint = self.ask.sam2_checkpoint()
            if checkpoint is None:
                self._set_mask_backend(self.masks.backend, save=False)  # the old choice
                return
            self.masks.sam2_checkpoint = checkpoint
            self._save_preference("sam2_checkpoint", str(checkpoint))
        self._set_mask_backend(backend)

    def _set_mask_backend(self, backend: str, save: bool = True) -> None:
        """Who draws the masks of the next tracking run (core.segment.backends)."""
        self.masks.backend = backend
        name = next(n for n, b in BACKEND_ACTIONS.items() if b == backend)
        self.actions_by_name[name].setChecked(True)
        if save:
            self._save_preference("mask_backend", backend)

    def _set_device(self, device: str, save: bool = True) -> None:
        """Where the fits and the tracker's edge network compute (core.device; the jobs
        resolve the name off the GUI thread)."""
        self.fits.device = self.masks.device = device
        self.actions_by_name[f"device_{device}"].setChecked(True)
        if save:
            self._save_preference("compute_device", device)

    def _on_cuda_probed(self, available: bool) -> None:
        """Offer CUDA where torch sees a GPU; elsewhere say why not, and compute a stored
        CUDA choice on what auto finds (the CPU) without forgetting it."""
        action = self.actions_by_name["device_cuda"]
        action.setEnabled(available)
        action.setToolTip("" if available else NO_CUDA)
        if not available and self.fits.device == CUDA:
            self._set_device(AUTO, save=False)

    def _show_error(self, title: str, text: str) -> None:
        self.ask.warn(title, text)

    # ------------------------------------------------------------------ clips and frames
    def _on_session_closed(self) -> None:
        self.playback.stop()
        self.loader.set_source(None)

    def _on_session_opened(self, session: ClipSession) -> None:
        media = session.source.clip
        self.loader.set_source(session.source)
        self.playback.set_clip(media.num_frames, media.fps)
        self.timeline.set_clip(media.num_frames, media.fps)
        try:
            self._show_telemetry()
            self._update_marks()
            self._check_camera()
            measurement = self.model.current_measurement()
            target = measurement.frame_idx if measurement is not None else self._pending_frame
            self._pending_frame = None
            self.go_to_frame(target if target is not None else 0, force=True)
        finally:  # a step that failed is reported (ui/crash_handler.py); the results still
            self.results.refresh()  # follow the open clip, not "the clip is still opening"
            self.canvas.setFocus()

    def _on_telemetry_changed(self) -> None:
        self._show_telemetry()
        self._update_status()
        self.results.refresh()

    def _check_camera(self) -> None:
        """A lasting red warning while the clip has no camera, or the camera's image size is
        not the clip's."""
        session = self.state.session
        if session is None:
            self.camera_warning.clear()
            return
        media = session.source.clip
        clip = self.model.project.clips[session.clip_idx]
        if clip.camera is None:
            self.camera_warning.setText(CAMERA_UNKNOWN)
            self.camera_warning.setToolTip("nothing is measured until the clip has a camera")
            return
        mismatch = preset_resolution_mismatch(clip.camera, media.width_px, media.height_px)
        self.camera_warning.setText("camera size ≠ clip: Clip → Camera…" if mismatch else "")
        self.camera_warning.setToolTip(mismatch or "")

    def _show_telemetry(self) -> None:
        telemetry = self.state.session.telemetry if self.state.session else None
        if telemetry is None:
            why = self.state.session.telemetry_error if self.state.session else ""
            self.timeline.set_altitude(None, None, None, why or "no altitude")
        else:
            self.timeline.set_altitude(telemetry.altitude_m, telemetry.is_interpolated,
                                       telemetry.is_missing, telemetry.source.describe())

    def _update_marks(self) -> None:
        clip_idx = self.model.clip_idx
        if clip_idx is None:
            return
        clip = self.model.project.clips[clip_idx]
        self.timeline.set_marks(sorted({m.frame_idx for a in clip.animals
                                        for m in a.measurements}))

    def go_to_frame(self, frame_idx: int, force: bool = False) -> None:
        """Show frame ``frame_idx`` (clamped to the clip)."""
        if self.state.session is None:
            self._pending_frame = frame_idx
            return
        frame_idx = int(np.clip(frame_idx, 0, self.state.session.source.clip.num_frames - 1))
        if frame_idx == self.state.frame_idx and not force:
            return
        self.state.frame_idx = frame_idx
        self.loader.request(frame_idx)
        self.timeline.set_frame(frame_idx)
        self.overlay.set_frame(frame_idx)
        self._update_status()

    def _seek(self, frame_idx: int) -> None:
        """A jump asked for by the user: playback stops (its next request would replace it)."""
        self.playback.stop()
        self.go_to_frame(frame_idx)

    def _on_frame_failed(self, frame_idx: int, why: str) -> None:
        self.playback.stop()
        self.notifier.status(f"frame {frame_idx}: {why}", 10_000)

    def _on_frame_ready(self, frame_idx: int, rgb: np.ndarray) -> None:
        if frame_idx != self.state.frame_idx:
            return
        self.canvas.set_frame(rgb)
        self.playback.frame_shown(frame_idx)
        self.state.frame_shown.emit(frame_idx)

    def _update_status(self) -> None:
        if self.state.session is None:
            self.status_label.setText("")
            return
        media = self.state.session.source.clip
        parts = [f"frame {self.state.frame_idx} of 0–{media.num_frames - 1}"]
        if media.num_frames > 1:
            parts.append(f"{self.state.frame_idx / media.fps:.2f} s")
        clip = self.model.project.clips[self.state.session.clip_idx]
        try:
            altitude, source = self.sessions.altitude_at(self.state.session.clip_idx,
                                                         self.state.frame_idx)
        except InputError as exc:
            parts.append(f"altitude: {exc}")
        else:
            telemetry = self.state.session.telemetry
            how = "interpolated" if telemetry.is_interpolated[self.state.frame_idx] else "sampled"
            where = f"{telemetry.source.kind}, {source}, {how}"
            try:
                calibrated = self.sessions.calibrated_altitude(self.state.session.clip_idx,
                                                               altitude)
            except InputError as exc:
                calibrated, where = None, f"{where}; calibration not used: {exc}"
            if calibrated is not None:  # what the results measure with
                where = f"calibrated by {clip.altitude_calibration!r}; {altitude:.2f} m {where}"
                altitude = calibrated
            parts.append(f"altitude {altitude:.2f} m ({where})")
            parts.append(_gsd_text(clip.camera, clip.preset_name, altitude))
        if clip.lens is not None:
            parts.append("through the lens model")
        self.status_label.setText(" · ".join(parts))

    def _on_cursor_moved(self, u: float, v: float) -> None:
        self.cursor_label.setText(f"x {u:.0f}, y {v:.0f} px")

    # ------------------------------------------------------------------ model observers
    def _on_model_changed(self, change: Change) -> None:
        self._sync_mirror_actions()
        if change.kind == "measurement":
            return  # a drag step: marks, clips, altitude and camera stay as they are
        self._update_marks()
        self._check_camera()
        self._update_status()  # a calibration or camera changes the altitude and GSD shown

    def _sync_mirror_actions(self) -> None:
        """Check the mirror action of the current measurement (both sides when none)."""
        measurement = self.model.current_measurement()
        side = measurement.mirror_side if measurement is not None else None
        for name, action_side in MIRROR_ACTIONS.items():
            self.actions_by_name[name].setChecked(action_side == side)

    def _on_selection_changed(self) -> None:
        self._sync_mirror_actions()
        if self.state.session_for(self.model.clip_idx) is None:
            self.sessions.open_current()
            return
        measurement = self.model.current_measurement()
        if measurement is not None and measurement.frame_idx != self.state.frame_idx:
            self.go_to_frame(measurement.frame_idx)

    def _update_title(self) -> None:
        path = self.model.path
        name = path.name if path else "untitled"
        self.setWindowTitle(f"{name}{' *' if self.model.is_dirty else ''} — {APP_NAME}")

    def closeEvent(self, event: QCloseEvent) -> None:  # noqa: N802 (Qt's name)
        if not self.files.may_leave_project():
            event.ignore()
            return
        self._save_layout()
        self.shutdown()
        event.accept()

    def _save_layout(self) -> None:
        """The window's size and place and its docks' layout, for the next start."""
        self._save_preference(LAYOUT_PREFERENCE, {
            "geometry": bytes(self.saveGeometry().toBase64()).decode("ascii"),
            "docks": bytes(self.saveState(LAYOUT_VERSION).toBase64()).decode("ascii")})

    def _restore_layout(self) -> bool:
        """The layout ``_save_layout`` stored, where there is a readable one (True)."""
        stored = load_preferences().get(LAYOUT_PREFERENCE)
        if not isinstance(stored, dict) or not all(
                isinstance(stored.get(key), str) for key in ("geometry", "docks")):
            return False
        self.restoreGeometry(QByteArray.fromBase64(stored["geometry"].encode("ascii")))
        return self.restoreState(QByteArray.fromBase64(stored["docks"].encode("ascii")),
                                 LAYOUT_VERSION)

    def shutdown(self) -> None:
        """Stop every worker thread (closing; a thread left running aborts Qt on exit)."""
        self.sessions.close()
        self.loader.shutdown()
        self.results.shutdown()
        self.exports.shutdown()
        self.fits.shutdown()
        self.masks.shutdown()
        self.scans.shutdown()
        self.intake.shutdown()
        self.files.shutdown()
        self.jobs.wait()
        self.probe.wait()

    # ------------------------------------------------------------------ actions: File
    def on_open(self) -> None:
        path = self.ask.media_to_open()
        if path is not None:
            self.files.open_path(path)

    def on_open_folder(self) -> None:
        path = self.ask.frames_folder("Open a folder of numbered frames")
        if path is not None:
            self.files.open_path(path)

    def on_add_media(self) -> None:
        if self.model.path is None:
            self.on_open()
            return
        path = self.ask.media_to_add()
        if path is not None:
            self.files.add_media(path)

    def on_add_folder(self) -> None:
        if self.model.path is None:
            self.on_open_folder()
            return
        path = self.ask.frames_folder("Add a folder of numbered frames")
        if path is not None:
            self.files.add_media(path)

    def on_add_clips(self) -> None:
        videos = self.ask.videos_to_add()
        if videos:
            self.intake.add(videos)

    def on_add_clip_folder(self) -> None:
        folder = self.ask.frames_folder("Add a folder of clips (each with its SRT beside it)")
        if folder is not None:
            self.intake.add([folder])

    def _fill_recent_menu(self) -> None:
        self.recent_menu.clear()
        for path in recent_projects():
            self.recent_menu.addAction(str(path), lambda p=path: self.files.open_path(p))

    def on_save(self) -> None:
        if self.model.path is None:
            self.on_save_as()
        else:
            self.files.save()

    def on_save_as(self) -> None:
        path = self.ask.save_path(self.model.path)
        if path is not None:
            self.files.save(path)

    def on_export_frame(self) -> None:
        self.exports.export_frame()

    def on_export_animal(self) -> None:
        self.exports.export_animal()

    def on_export_project(self) -> None:
        self.exports.export_project()

    def on_export_comparison(self) -> None:
        self.exports.export_comparison()

    def on_export_meshes(self) -> None:
        self.exports.export_meshes()

    def on_quit(self) -> None:
        self.close()

    # ------------------------------------------------------------------ actions: Edit, View
    def on_undo(self) -> None:
        self.model.undo_stack.undo()

    def on_redo(self) -> None:
        self.model.undo_stack.redo()

    def on_handle_style(self) -> None:
        style = self.ask.handle_style(self.overlay.style)
        if style is not None:
            self.overlay.set_style(style)
            self._save_preference("handle_style", asdict(style))

    def on_fit_view(self) -> None:
        self.canvas.fit_to_window()

    def on_play(self) -> None:
        if self.state.session is not None:
            self.playback.toggle()

    def _step(self, delta: int) -> None:
        self._seek(self.state.frame_idx + delta)

    def on_first_frame(self) -> None:
        self._seek(0)

    def on_last_frame(self) -> None:
        if self.state.session is not None:
            self._seek(self.state.session.source.clip.num_frames - 1)

    def on_go_to_frame(self) -> None:
        if self.state.session is None:
            return
        last = self.state.session.source.clip.num_frames - 1
        frame_idx = self.ask.frame_number(self.state.frame_idx, last)
        if frame_idx is not None:
            self._seek(frame_idx)

    def on_show_masks(self, checked: bool) -> None:
        self.masks.layer.set_visible(checked)

    def on_track_click(self) -> None:
        self.masks.arm_click_seed()

    def on_retrack(self) -> None:
        self.masks.retrack_here()

    def on_track_every_frame(self) -> None:
        self.masks.retrack_here(every_frame=True)

    def on_fit_silhouette(self, checked: bool) -> None:
        self.fits.set_silhouette_visible(checked)

    def on_auto_zoom(self, checked: bool) -> None:
        self.overlay.auto_zoom = checked
        self._save_preference("auto_zoom", checked)

    def _save_preference(self, key: str, value: object) -> None:
        try:
            save_preference(key, value)
        except OSError as exc:
            self.notifier.status(f"preference not saved: {exc.strerror or exc}", 10_000)

    # ------------------------------------------------------------------ actions: Clip
    def on_altitude(self) -> None:
        self.sessions.set_altitude()

    def on_camera(self) -> None:
        self.sessions.set_camera(self.project_panel.selected_clips())

    def on_lens(self) -> None:
        self.sessions.set_lens()

    def on_clear_lens(self) -> None:
        self.sessions.clear_lens()

    def on_calibrate_altitude(self) -> None:
        self.sessions.calibrate_altitude()

    def on_add_animal(self) -> None:
        self.animals.add_animal()

    def on_edit_animal(self) -> None:
        self.animals.edit_animal()

    def on_remove_animal(self) -> None:
        self.animals.remove_animal()

    def on_scan_clip(self) -> None:
        self.scans.scan_selected()

    def on_scan_all(self) -> None:
        self.scans.scan_unscanned()

    def on_stop_work(self) -> None:
        """Stop the tracking and the scans under way (each keeps what it has done)."""
        stopped = self.scans.cancel_all()
        if self.masks.tracker.is_running:
            self.masks.tracker.cancel()
            stopped = True
        if not stopped:
            self.notifier.status("nothing to stop: no tracking or scan is running", 5000)

    def on_next_clip(self) -> None:
        clip_idx = self.scans.next_clip_needing_work()
        if clip_idx is None:
            self.notifier.status("no clip needs work: every clip is scanned and each animal "
                                 "with a usable frame measured", 10_000)
            return
        self.model.select(clip_idx)

    def _show_scan(self, scan: object) -> None:
        clip_idx = self.model.clip_idx
        rejected = () if clip_idx is None else self.model.project.clips[clip_idx].rejected_frames
        self.picker.set_scan(scan, rejected)

    def _fetch_thumbnails(self, scores: list) -> None:
        clip_idx, scan = self.model.clip_idx, self.picker.scan
        if clip_idx is None:
            return
        self.scans.thumbnails(clip_idx, scores, THUMBNAIL_PX,
                              lambda pictures: self.picker.set_thumbnails(pictures, scan))

    def _measure_scanned_frame(self, number: int, frame_idx: int) -> None:
        """Measure scan animal ``number`` (the project's "dolphin N") on ``frame_idx``."""
        clip_idx = self.model.clip_idx
        if clip_idx is None or self.state.session_for(clip_idx) is None:
            self.notifier.status("the clip is still opening: pick the frame again in a "
                                 "moment", 5000)
            return
        self.animals.select_scan_animal(clip_idx, number)
        self._seek(frame_idx)
        self.on_measure_frame()
        self.canvas.setFocus()

    # ------------------------------------------------------------------ actions: Measure
    def on_measure_frame(self) -> None:
        """Start a measurement of the current animal on the current frame."""
        if self.animals.measure_frame():
            self._set_mode("length")

    def _set_mode(self, mode: str) -> None:
        """The overlay's mode and its checked action ("length" or "widths")."""
        self.actions_by_name[f"{mode}_mode"].setChecked(True)
        self.overlay.set_mode(mode)

    def on_remove_measurement(self) -> None:
        self.animals.remove_measurement()

    def on_length_mode(self) -> None:
        self.overlay.set_mode("length")

    def on_widths_mode(self) -> None:
        self.overlay.set_mode("widths")

    def on_reverse(self) -> None:
        self.overlay.reverse_direction()

    def on_delete_point(self) -> None:
        self.overlay.delete_selected_point()

    def on_next_handle(self) -> None:
        self.overlay.next_handle()

    def on_previous_handle(self) -> None:
        self.overlay.previous_handle()

    def on_skip_station(self) -> None:
        self.overlay.skip_station()

    def on_suggest_edges(self) -> None:
        """Widths where each station's perpendicular leaves the clip's mask."""
        measurement = self.model.current_measurement()
        if self.state.session is None or measurement is None or not measurement.has_length:
            self.notifier.error("Suggest edges", "measure a length on this frame first")
            return
        key, frame_idx = self.model.current_key(), measurement.frame_idx

        def apply(mask: np.ndarray) -> None:
            if self.model.current_key() != key or self.state.frame_idx != frame_idx:
                self.notifier.status("edges not suggested: another frame is shown now",
                                     10_000)
                return
            try:
                if self.overlay.suggest_edges(mask):
                    self._set_mode("widths")  # the suggested edges are drawn in widths mode
            except InputError as exc:
                self.notifier.error("Suggest edges", str(exc))

        self.masks.read_frame_mask(frame_idx, apply, "Suggest edges")

    def on_masks(self) -> None:
        """Choose the clip's masks (a PNG folder, an .npz or a mask video), checked first."""
        clip_idx = selected_clip(self.model, self.notifier)
        if clip_idx is None or self.state.session is None:
            return
        masks = self.ask.masks_source()
        if masks is not None:
            self.masks.use_masks(clip_idx, masks)

    # ------------------------------------------------------------------ actions: Help
    def on_manual(self) -> None:
        self.ask.show_manual()

    def on_shortcuts(self) -> None:
        self.ask.show_shortcuts()

    def on_about(self) -> None:
        self.ask.show_about()
