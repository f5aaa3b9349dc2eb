"""What the app's controllers observe instead of the window: the open clip and the frame on
screen (``ViewerState``), and one place to report errors and status lines (``Notifier``).

The window owns both, sets them and shows what the notifier says; controllers take them in
their constructor and never reach into the window, so each can be built and tested with the
views it draws on alone.
"""

from PySide6.QtCore import QObject, Signal

from dolphinfit.ui.state.clip_session import ClipSession


class ViewerState(QObject):
    """The open clip's session (None while none is open) and the frame asked for.

    ``session_opened(clip_idx)`` fires once the session is set up, ``session_closed`` when it
    is closed, ``frame_shown(idx)`` when frame ``idx`` is on screen (``frame_idx`` is set when
    it is asked for, before it is read)."""

    session_opened = Signal(int)
    session_closed = Signal()
    frame_shown = Signal(int)

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.session: ClipSession | None = None
        self.frame_idx = 0

    def session_for(self, clip_idx: int | None) -> ClipSession | None:
        """The open session when it is clip ``clip_idx``'s, else None."""
        session = self.session
        return session if session is not None and session.clip_idx == clip_idx else None

    def close(self) -> None:
        """Close the open session, if any, and say so."""
        if self.session is not None:
            self.session.close()
            self.session = None
            self.session_closed.emit()


class Notifier(QObject):
    """Errors (a dialog) and status lines (the status bar) from the app's controllers."""

    error_raised = Signal(str, str)    # title, text
    status_shown = Signal(str, int)    # text, milliseconds (0: until replaced)

    def error(self, title: str, text: str) -> None:
        """Tell the user something failed."""
        self.error_raised.emit(title, text)

    def status(self, text: str, timeout_ms: int = 0) -> None:
        """A line in the status bar."""
        self.status_shown.emit(text, timeout_ms)


def selected_clip(model, notifier: Notifier) -> int | None:
    """The selected clip of ``model`` (a ProjectModel); None, with an error said, when none."""
    if model.clip_idx is None:
        notifier.error("No clip", "open a clip, an image or a folder of frames first")
    return model.clip_idx

