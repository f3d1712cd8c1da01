"""Exceptions of the viewer; all derive from :class:`ViewerError`."""

from __future__ import annotations

from ..diagnostics import RobocopError


class ViewerError(RobocopError):
    """Root of the viewer's exceptions (bad options, unreadable replay files)."""


class ViewerConnectionError(ViewerError):
    """The Meshcat server could not be started or did not answer in time.

    Attributes:
        zmq_url: The server's ZeroMQ address, or ``None`` when it never started.
    """

    def __init__(self, message: str, zmq_url: str | None = None):
        self.zmq_url = zmq_url
        super().__init__(message)
