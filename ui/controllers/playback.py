"""Playback at the clip's frame rate that never queues frames behind decoding.

The timer ticks at the clip's fps, but the next frame is asked for only once the previous one
was shown (``frame_shown``): when decoding is slower than the clip, playback slows down to the
decoding rate instead of piling up requests.
"""

from PySide6.QtCore import QObject, Qt, QTimer, Signal, Slot


class Playback(QObject):
    """Plays from the shown frame to the last one, then stops.

    Connect ``frame_requested`` to the frame loader and call ``frame_shown`` whenever a frame
    is displayed (played or not). Connect user seeks to ``stop``: a playback request issued
    before the seek's frame arrives would otherwise overtake it in the newest-only loader.
    Connect the loader's ``failed`` to ``stop`` too: a frame that never shows stalls playback.
    """

    frame_requested = Signal(int)
    playing_changed = Signal(bool)

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self._num_frames = 0
        self._shown = 0  # the frame on screen
        self._awaiting: int | None = None  # the frame asked for and not yet shown
        self._tick_missed = False  # a tick came while awaiting: ask as soon as it is shown
        self._timer = QTimer(self)
        self._timer.setTimerType(Qt.TimerType.PreciseTimer)
        self._timer.timeout.connect(self._tick)

    @property
    def is_playing(self) -> bool:
        return self._timer.isActive()

    def set_clip(self, num_frames: int, fps: float) -> None:
        """A new clip: playback stops and starts from frame 0 next time."""
        self.stop()
        self._num_frames = num_frames
        self._shown = 0
        self._timer.setInterval(max(1, round(1000 / fps)))

    @Slot()
    def toggle(self) -> None:
        if self.is_playing:
            self.stop()
        else:
            self.play()

    @Slot()
    def play(self) -> None:
        """Start playing; from frame 0 if the last frame is shown."""
        if self.is_playing or self._num_frames < 2:
            return
        if self._shown >= self._num_frames - 1:
            self._shown = -1
        self._awaiting = None
        self._tick_missed = False
        self._timer.start()
        self.playing_changed.emit(True)
        self._tick()

    @Slot()
    def stop(self) -> None:
        if not self.is_playing:
            return
        self._timer.stop()
        self._awaiting = None
        self.playing_changed.emit(False)

    @Slot(int)
    def frame_shown(self, frame_idx: int) -> None:
        """Frame ``frame_idx`` is on screen now; any frame shown ends the wait for the next."""
        self._shown = frame_idx
        if self._awaiting is None:
            return
        self._awaiting = None
        if self._tick_missed:
            self._tick_missed = False
            self._tick()

    def _tick(self) -> None:
        if self._awaiting is not None:
            self._tick_missed = True
        elif self._shown >= self._num_frames - 1:
            self.stop()
        else:
            self._awaiting = self._shown + 1
            self.frame_requested.emit(self._awaiting)
