"""Exceptions of the controller; all derive from :class:`RobocopError` and carry data."""

from __future__ import annotations

from typing import Any, Sequence

from ..diagnostics import RobocopError, did_you_mean


class ControlError(RobocopError):
    """Root of the controller's exceptions."""


def _listing(name: str, available: Sequence[str]) -> str:
    hint = did_you_mean(name, available)
    names = ", ".join(sorted(available)) or "none"
    return (f" ({hint})" if hint else "") + f"; available: {names}"


class UnknownSolver(ControlError):
    """A QP solver name that is not installed.

    Attributes:
        name: The requested solver.
        available: Names of the installed qpsolvers backends.
    """

    def __init__(self, name: str, available: Sequence[str]):
        self.name = name
        self.available = tuple(sorted(available))
        super().__init__(
            f"unknown QP solver '{name}'{_listing(name, self.available)}; more backends "
            "install with pip (e.g. 'pip install qpsolvers[open_source_solvers]')")


class UnknownKind(ControlError):
    """A task, constraint, interpolator or feedback type that is not registered.

    Attributes:
        category: ``"task"``, ``"constraint"``, ``"interpolator"`` or ``"feedback"``.
        name: The requested type.
        available: The registered types of that category.
    """

    def __init__(self, category: str, name: str, available: Sequence[str]):
        self.category = category
        self.name = name
        self.available = tuple(sorted(available))
        super().__init__(f"unknown {category} type '{name}'{_listing(name, self.available)}")


class UnknownName(ControlError):
    """A body, joint group, task or constraint name that does not exist.

    Attributes:
        category: What was looked up (``"body"``, ``"joint group"``, ``"task"``...).
        name: The requested name.
        available: The valid names.
    """

    def __init__(self, category: str, name: str, available: Sequence[str]):
        self.category = category
        self.name = name
        self.available = tuple(sorted(available))
        super().__init__(f"unknown {category} '{name}'{_listing(name, self.available)}")


class DuplicateName(ControlError):
    """A task or constraint added under a name already in use.

    Attributes:
        category: ``"task"`` or ``"constraint"``.
        name: The name in use.
    """

    def __init__(self, category: str, name: str):
        self.category = category
        self.name = name
        super().__init__(f"a {category} named '{name}' already exists")


class InvalidParameter(ControlError):
    """A parameter value of the wrong type, shape or range.

    Attributes:
        owner: The task, constraint, interpolator or feedback loop it was given to.
        parameter: The parameter's name.
        value: The rejected value.
        expected: What would have been accepted.
    """

    def __init__(self, owner: str, parameter: str, value: Any, expected: str):
        self.owner = owner
        self.parameter = parameter
        self.value = value
        self.expected = expected
        shown = value.tolist() if hasattr(value, "tolist") else value   # numpy: as a list
        super().__init__(f"{owner}: invalid {parameter} {shown!r}: expected {expected}")


class JointGroupOutsideController(ControlError):
    """A task or constraint on joints that the controller does not command.

    Attributes:
        group: The task's or constraint's joint group.
        joints: Its joints that are not in the controlled group.
        controlled: The controlled joint group.
    """

    def __init__(self, group: str, joints: Sequence[str], controlled: str):
        self.group = group
        self.joints = tuple(joints)
        self.controlled = controlled
        super().__init__(f"joint group '{group}' has joints outside the controlled group "
                         f"'{controlled}': {', '.join(self.joints)}")


class PartFailed(ControlError):
    """A task or constraint raised while the controller computed its part of the QP;
    ``owner`` names it (``task 'arms'``), the cause is chained."""

    def __init__(self, owner: str, error: BaseException):
        self.owner = owner
        cause = str(error) if isinstance(error, RobocopError) else (
            f"{type(error).__name__}: {error}" if str(error) else type(error).__name__)
        super().__init__(f"{owner}: {cause}")
