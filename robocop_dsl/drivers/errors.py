"""The drivers' exceptions, rooted in :class:`robocop_dsl.diagnostics.RobocopError`."""

from __future__ import annotations

from ..diagnostics import RobocopError


class DriverFault(RobocopError):
    """The robot stopped answering: raised by a driver's ``connect()``, ``read()`` or
    ``write()``.

    Args:
        driver: The driver's description (its ``repr``).
        reason: What went wrong, in the robot's words ("connection closed by the robot",
            "no state for 0.25 s").
    """

    def __init__(self, driver: str, reason: str):
        self.driver = driver
        self.reason = reason
        super().__init__(f"{driver}: {reason}")


class ThreadOwnershipError(RobocopError):
    """A buffer side was used from a thread that does not own it.

    Args:
        buffer: The buffer's description.
        method: The method that was called (``read``, ``write`` or ``sync``).
        owner: Name of the thread that owns this side.
        caller: Name of the calling thread.
    """

    def __init__(self, buffer: str, method: str, owner: str, caller: str):
        self.buffer = buffer
        self.method = method
        self.owner = owner
        self.caller = caller
        hint = ("read() and write() belong to the controller thread that owns the world; "
                "a driver thread uses sync()" if method != "sync" else
                "sync() belongs to the single thread feeding this buffer")
        super().__init__(f"{buffer}.{method}() called from thread '{caller}' but this side "
                         f"belongs to thread '{owner}' ({hint})")


class DriverConfigError(RobocopError):
    """A driver processor's options cannot be used (unknown type, bad rate or port)."""
