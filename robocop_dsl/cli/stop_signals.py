"""SIGINT and SIGTERM taken over while a command runs: the first one is recorded and
handed to :meth:`StopSignals.stop`; later ones change nothing. The previous handlers
come back on exit."""

from __future__ import annotations

import signal
import threading


class StopSignals:
    """While entered (from the main thread), the first SIGINT or SIGTERM is recorded
    and :meth:`stop` is called; a command's subclass says what stopping is.

    Attributes:
        received: The first signal's number, or ``None``.
    """

    SIGNALS = (signal.SIGINT, signal.SIGTERM)

    def __init__(self):
        self.received: int | None = None
        self._previous: dict = {}

    def __enter__(self):
        if threading.current_thread() is threading.main_thread():
            for number in self.SIGNALS:
                self._previous[number] = signal.signal(number, self._handle)
        return self

    def __exit__(self, *exc) -> None:
        self.release()

    def release(self) -> None:
        """Give the signals their previous handlers back (again: nothing)."""
        for number, handler in self._previous.items():
            signal.signal(number, handler)
        self._previous = {}

    def _handle(self, number: int, frame) -> None:
        if self.received is None:
            self.received = number
            self.stop()

    def stop(self) -> None:
        """What the first signal does."""
