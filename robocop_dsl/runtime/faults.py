"""What raised in the loop, in the mission's words, and an exception as one line."""

from __future__ import annotations

from ..control.exceptions import PartFailed
from ..diagnostics import RobocopError
from .statechart import StepFailed


def fault_place(error: BaseException, state: str) -> str:
    """What raised ``error``, in the mission's words: the clause or block, its action
    and the state, and the task or constraint when one raised (the configuration
    ``state`` otherwise)."""
    where, cause = None, error
    if isinstance(error, StepFailed):
        where, cause = error.where, error.__cause__
    owner = cause.owner if isinstance(cause, PartFailed) else None
    if where is not None:
        return f"{where}, {owner}" if owner else where
    return f"{owner or 'controller'} in state '{state}'"


def origin(error: BaseException) -> BaseException:
    """The exception that started ``error``, through the wrappers that name where it
    was raised."""
    while isinstance(error, (StepFailed, PartFailed)) and error.__cause__ is not None:
        error = error.__cause__
    return error


def error_text(error: BaseException) -> str:
    """An exception as one line: its type (unless a RobocopError) and message."""
    if isinstance(error, RobocopError):
        return str(error)
    return f"{type(error).__name__}: {error}" if str(error) else type(error).__name__
