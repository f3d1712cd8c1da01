"""Abstract constraint: linear bounds on the joint-velocity command, held at every level."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from ..state import ControlState


class Constraint(ABC):
    """``lower <= J dq <= upper`` for the command ``dq``, enabled when created.

    Subclasses implement :meth:`compute_jacobian` and :meth:`compute_bounds`; the
    controller puts their rows into the QP through :meth:`write_rows`, which a subclass
    may override to write them in place. A constraint whose rows are joint velocities
    sets :attr:`box_columns` (the columns of the command it bounds) so the solver can
    treat it as box bounds.

    Args:
        name: The constraint's name.
        state: The controller's state.
    """

    kind = "constraint"
    box_columns: np.ndarray | None = None

    def __init__(self, name: str, state: ControlState):
        self.name = name
        self.state = state
        self._enabled = True
        state.revision += 1

    @property
    @abstractmethod
    def rows(self) -> int:
        """Number of constrained quantities."""

    @abstractmethod
    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        """Hook: rows x dofs matrix applied to the command."""

    @abstractmethod
    def compute_bounds(self, state: ControlState) -> tuple[np.ndarray, np.ndarray]:
        """Hook: lower and upper bounds of the rows (``inf`` where unbounded)."""

    def write_rows(self, state: ControlState, jacobian: np.ndarray, lower: np.ndarray,
                   upper: np.ndarray) -> None:
        """Write the rows into the QP: ``jacobian`` (rows x dofs), ``lower`` and
        ``upper`` are views of the QP's arrays, the same objects from cycle to cycle
        while the QP's structure lasts. By default, the hooks' results copied in."""
        lower[:], upper[:] = self.compute_bounds(state)
        jacobian[:] = self.compute_jacobian(state)

    @property
    def enabled(self) -> bool:
        """Whether the constraint holds."""
        return self._enabled

    @enabled.setter
    def enabled(self, value: bool) -> None:
        self._enabled = bool(value)
        self.state.revision += 1

    def enable(self) -> None:
        """Enable: the constraint holds from the next cycle."""
        self.enabled = True

    def disable(self) -> None:
        """Disable: the controller ignores the constraint."""
        self.enabled = False

    def joint_limits(self) -> tuple | None:
        """Hook: ``(columns, min_position, max_position, max_velocity,
        max_acceleration)`` the constraint adds to the controller's joint limits table
        (:mod:`robocop_dsl.safety.limits`) instead of rows, else ``None``."""
        return None

    def release(self) -> None:
        """Hook: the controller no longer holds the constraint."""

    @property
    def label(self) -> str:
        """``kind 'name'``, for messages."""
        return f"{self.kind} '{self.name}'"

    def parameters(self) -> dict:
        """The constraint's parameters by name."""
        return {}

    def configure(self, **parameters) -> None:
        """Change parameters by name (validated like the constructor's)."""
        for key, value in parameters.items():
            setattr(self, key, value)

    def describe(self) -> str:
        """What the constraint acts on, for ``repr``."""
        return ""

    def __repr__(self) -> str:
        parameters = ", ".join(f"{key}={_short(value)}" for key, value in self.parameters().items())
        return (f"{type(self).__name__}({self.name!r}, {self.describe()}{parameters}, "
                f"enabled={self.enabled})")


def _short(value):
    if isinstance(value, np.ndarray):
        if value.size and np.all(value == value.flat[0]):
            return repr(float(value.flat[0]))
        return repr([round(float(v), 6) for v in value])
    return repr(value)
