"""Ctrl-C and SIGTERM, as the operating system delivers them, taken as a request to stop: a
long command (learning, a run) ends the step under way, keeps what it made and says so,
rather than dying with its output half written."""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

# The exit status of a process stopped by a signal, as a shell reports one killed by it
# (128 + the signal's number): scripts tell an interrupted command from a failed one.
STOPPED_EXIT = {"SIGINT": 128 + signal.SIGINT, "SIGTERM": 128 + signal.SIGTERM}


class Interrupted:
    """Remembers the first SIGINT/SIGTERM, for a loop to stop at its next step."""

    def __init__(self) -> None:
        self.signal_name: str | None = None

    def __call__(self, signum: int, frame: FrameType | None) -> None:
        self.signal_name = self.signal_name or signal.Signals(signum).name

    def reason(self) -> str | None:
        """The signal that asked to stop ("SIGINT"), or None while none has."""
        return self.signal_name


@contextmanager
def catching_signals() -> Iterator[Interrupted]:
    """SIGINT and SIGTERM remembered rather than raised while the block runs."""
    interrupted = Interrupted()
    if threading.current_thread() is not threading.main_thread():
        # Only the main thread may set handlers (a Dask worker learns in a thread of its
        # own); there the process's own handling of signals stands.
        yield interrupted
        return
    previous = {s: signal.signal(s, interrupted) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield interrupted
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
