"""Interpolators: how a task's reference moves towards its target."""

from __future__ import annotations

from ..exceptions import InvalidParameter, UnknownKind
from .base import Interpolator
from .cubic import CubicInterpolator
from .linear import LinearInterpolator
from .none import NoInterpolator
from .otg import OTGInterpolator
from .quintic import QuinticInterpolator
from .timed import TimedInterpolator

INTERPOLATORS: dict[str, type[Interpolator]] = {
    cls.kind: cls for cls in (OTGInterpolator, LinearInterpolator, CubicInterpolator,
                              QuinticInterpolator, NoInterpolator)
}


def make_interpolator(spec, **parameters) -> Interpolator:
    """An interpolator from an instance, or a registered kind and its parameters.

    Args:
        spec: An :class:`Interpolator` (returned as is), a kind (``"otg"``, ``"linear"``,
            ``"cubic"``, ``"quintic"``, ``"none"``) or ``None`` (``"none"``).
        **parameters: The kind's parameters, e.g. ``duration=2.0``.

    Raises:
        UnknownKind: the kind is not registered.
        InvalidParameter: a parameter is missing or invalid.
    """
    if isinstance(spec, Interpolator):
        return spec
    kind = "none" if spec is None else spec
    if kind not in INTERPOLATORS:
        raise UnknownKind("interpolator", str(kind), INTERPOLATORS)
    try:
        return INTERPOLATORS[kind](**parameters)
    except TypeError as error:
        raise InvalidParameter(kind, "parameters", parameters, str(error)) from error


__all__ = [
    "CubicInterpolator", "INTERPOLATORS", "Interpolator", "LinearInterpolator",
    "NoInterpolator", "OTGInterpolator", "QuinticInterpolator", "TimedInterpolator",
    "make_interpolator",
]
