"""Feedback loops: how a task's error becomes a corrective velocity."""

from __future__ import annotations

from ..exceptions import InvalidParameter, UnknownKind
from .base import FeedbackLoop
from .pid import PIDFeedback
from .proportional import ProportionalFeedback

FEEDBACK_LOOPS: dict[str, type[FeedbackLoop]] = {
    cls.kind: cls for cls in (ProportionalFeedback, PIDFeedback)
}


def make_feedback_loop(spec, **parameters) -> FeedbackLoop:
    """A feedback loop from an instance, or a registered kind and its parameters.

    Args:
        spec: A :class:`FeedbackLoop` (returned as is) or a kind (``"proportional"``,
            ``"pid"``).
        **parameters: The kind's parameters, e.g. ``gain=5.0``.

    Raises:
        UnknownKind: the kind is not registered.
        InvalidParameter: a parameter is invalid.
    """
    if isinstance(spec, FeedbackLoop):
        return spec
    if spec not in FEEDBACK_LOOPS:
        raise UnknownKind("feedback", str(spec), FEEDBACK_LOOPS)
    try:
        return FEEDBACK_LOOPS[spec](**parameters)
    except TypeError as error:
        raise InvalidParameter(spec, "parameters", parameters, str(error)) from error


__all__ = ["FEEDBACK_LOOPS", "FeedbackLoop", "PIDFeedback", "ProportionalFeedback",
           "make_feedback_loop"]
