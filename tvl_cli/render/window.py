"""A window on screen showing frames as a robot drives (`tvl run --view window`, and the
Gymnasium environment's `human` render mode): the frames the replays draw, shown by
matplotlib in whichever window system it finds.

This is the one module that opens a window, so the one that uses pyplot: its figure
manager is how matplotlib picks a window system and opens a window in it. Every picture
saved to a file is drawn on a Figure of its own.
"""

from __future__ import annotations

import os
import sys
import time
from typing import Any

import numpy as np

from tvl_cli.core.errors import EnvironmentFailure

REFRESH_PER_S = 15.0  # redraws a wall second: smooth to the eye, cheap beside the simulation
LAST_FRAME_S = 2.0  # how long the last frame stays up before the window closes


class FrameWindow:
    """A window of RGB frames of one size, each shown in place of the last."""

    def __init__(self, title: str, size_px: tuple[int, int], dpi: float) -> None:
        """`size_px` (height, width) of the frames; `dpi` the frames were drawn at, so that
        they show at their own size."""
        pyplot = _window_pyplot()
        height, width = size_px
        try:
            self.figure = pyplot.figure(title, figsize=(width / dpi, height / dpi), dpi=dpi)
        except Exception as error:  # each window system fails in its own way (Tk's TclError)
            raise EnvironmentFailure(f"cannot open a window: {_one_line(error)}") from None
        axes = self.figure.add_axes((0.0, 0.0, 1.0, 1.0))
        axes.set_axis_off()
        self.image = axes.imshow(np.full((height, width, 3), 255, dtype=np.uint8))
        self._pyplot = pyplot
        self._shown_at = -float("inf")
        pyplot.show(block=False)

    @property
    def is_open(self) -> bool:
        """False once the user has closed the window."""
        return bool(self._pyplot.fignum_exists(self.figure.number))

    def due(self) -> bool:
        """Whether a frame shown now would be seen: REFRESH_PER_S a second at most."""
        return time.monotonic() - self._shown_at >= 1.0 / REFRESH_PER_S

    def show(self, frame: np.ndarray) -> None:
        """Show an (H, W, 3) uint8 frame in place of the last."""
        if not self.is_open:
            return
        self.image.set_data(frame)
        self.figure.canvas.draw_idle()
        self.figure.canvas.flush_events()
        self._shown_at = time.monotonic()

    def hold(self, seconds: float) -> None:
        """Keep the window answering (to be moved, resized, closed) until `seconds` after
        the last frame was shown."""
        remaining_s = seconds - (time.monotonic() - self._shown_at)
        if remaining_s > 0 and self.is_open:
            self.figure.canvas.start_event_loop(remaining_s)

    def close(self) -> None:
        self._pyplot.close(self.figure)


def display_available() -> bool:
    """Whether there is a display to open a window on: on Linux, one named by $DISPLAY or
    $WAYLAND_DISPLAY (elsewhere the desktop's own)."""
    if not sys.platform.startswith("linux"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def _window_pyplot() -> Any:
    """pyplot, with a backend that opens windows; EnvironmentFailure in one line if there
    is no display to open one on, or no window system matplotlib can use."""
    if not display_available():
        raise EnvironmentFailure(
            "no display to open a window on ($DISPLAY is not set); "
            "use --live to watch in the terminal"
        )
    import matplotlib
    from matplotlib import pyplot
    from matplotlib.backends import BackendFilter, backend_registry

    backend = matplotlib.get_backend().lower()
    windows = set(backend_registry.list_builtin(BackendFilter.INTERACTIVE)) - {"webagg", "nbagg"}
    if backend not in windows:
        # matplotlib falls back to drawing off screen where no window system it knows
        # answered: the display is unreachable, none is installed, or MPLBACKEND chose so.
        display = os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY") or "the screen"
        raise EnvironmentFailure(
            f"no window opens on {display}: matplotlib's backend is {backend}, which opens "
            "no windows (is the display reachable, and Tk, Qt or GTK for Python installed?)"
        )
    return pyplot


def _one_line(error: Exception) -> str:
    return " ".join(str(error).split()) or type(error).__name__
