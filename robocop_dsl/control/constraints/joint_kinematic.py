"""The ``joint_kinematic`` constraint: position, velocity and acceleration limits."""

from __future__ import annotations

import numpy as np

from ..exceptions import InvalidParameter, UnknownName
from ..parameters import vector_parameter
from ..state import ControlState
from ...safety.joint_box import JointBox
from ...safety.limits import JointLimits
from .base import Constraint


class JointKinematicConstraint(Constraint):
    """Joint limits of a group turned into bounds on the next velocity command.

    For each joint, with ``dt`` the time step and ``prev`` the previous command:

    - velocity: ``|dq| <= max_velocity``;
    - acceleration: ``|dq - prev| <= max_acceleration * dt``;
    - position: ``dq`` at most the viable speed towards ``max_position``, from which
      the joint still stops before it braking at half of ``max_acceleration`` in steps
      of ``dt`` (:mod:`robocop_dsl.safety.viable`); likewise towards ``min_position``.

    Velocity and acceleration limits never exceed the world's (the URDF's): a larger
    value given here is lowered to it. A continuous joint has no position limit by
    default; its position is its angle in (-pi, pi]. A joint outside its position
    range may not go further out, and is driven back as fast as its acceleration and
    velocity limits allow. When the acceleration bound conflicts with the others (e.g.
    after the state jumped), the velocity closest to ``prev`` within the others is taken
    and the controller reports the relaxation.

    Args:
        name: The constraint's name.
        state: The controller's state.
        group: The joint group (inside the controlled group).
        min_position: Lower positions [rad or m]; default the URDF's.
        max_position: Upper positions [rad or m]; default the URDF's.
        max_velocity: Speed limits [rad/s or m/s]; default and at most the URDF's.
        max_acceleration: Acceleration limits [rad/s^2 or m/s^2]; default and at most
            the world's (``inf`` when unknown: no acceleration bound).
    """

    kind = "joint_kinematic"

    def __init__(self, name: str, state: ControlState, group: str, *, min_position=None,
                 max_position=None, max_velocity=None, max_acceleration=None):
        super().__init__(name, state)
        self.group, self.box_columns = state.group_columns(group)
        self._jacobian = np.eye(state.dofs)[self.box_columns]
        group_ = self.group
        self._velocity_bound = self._vector("max_velocity", group_.max_velocity)
        self._acceleration_bound = self._vector("max_acceleration", group_.max_acceleration)
        self.min_position = group_.lower if min_position is None else min_position
        self.max_position = group_.upper if max_position is None else max_position
        self.max_velocity = group_.max_velocity if max_velocity is None else max_velocity
        self.max_acceleration = (group_.max_acceleration if max_acceleration is None
                                 else max_acceleration)

    def _vector(self, name: str, value, minimum=None) -> np.ndarray:
        return vector_parameter(self.label, name, value, len(self.box_columns),
                                minimum=minimum, strict=minimum is not None, allow_inf=True)

    @property
    def min_position(self) -> np.ndarray:
        """Lower position limits [rad or m]."""
        return self._min_position

    @min_position.setter
    def min_position(self, value) -> None:
        self._min_position = self._vector("min_position", value)
        self.state.revision += 1

    @property
    def max_position(self) -> np.ndarray:
        """Upper position limits [rad or m]."""
        return self._max_position

    @max_position.setter
    def max_position(self, value) -> None:
        self._max_position = self._vector("max_position", value)
        self.state.revision += 1

    @property
    def max_velocity(self) -> np.ndarray:
        """Speed limits [rad/s or m/s], the world's where those are lower."""
        return self._max_velocity

    @max_velocity.setter
    def max_velocity(self, value) -> None:
        self._max_velocity = np.minimum(self._vector("max_velocity", value, minimum=0.0),
                                        self._velocity_bound)
        self.state.revision += 1

    @property
    def max_acceleration(self) -> np.ndarray:
        """Acceleration limits [rad/s^2 or m/s^2], the world's where those are lower."""
        return self._max_acceleration

    @max_acceleration.setter
    def max_acceleration(self, value) -> None:
        self._max_acceleration = np.minimum(
            self._vector("max_acceleration", value, minimum=0.0), self._acceleration_bound)
        self.state.revision += 1

    @property
    def rows(self) -> int:
        return len(self.box_columns)

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return self._jacobian

    def joint_limits(self) -> tuple:
        """``(columns, min_position, max_position, max_velocity, max_acceleration)``: what
        the constraint adds to the controller's joint limits table
        (:func:`~robocop_dsl.safety.limits.joint_limits`)."""
        return (self.box_columns, self._min_position, self._max_position, self._max_velocity,
                self._max_acceleration)

    def compute_bounds(self, state: ControlState) -> tuple[np.ndarray, np.ndarray]:
        """The constraint's bounds alone (the controller meets every enabled
        ``joint_kinematic`` constraint with the world's limits in one table instead)."""
        limits = JointLimits(self._min_position, self._max_position, self._max_velocity,
                             self._max_acceleration, (self.label,) * len(self.box_columns))
        previous = state.previous_command[self.box_columns]
        box = JointBox(limits, state.time_step)
        lower, upper = np.zeros(len(previous)), np.zeros(len(previous))
        box.write(state.group_positions[self.box_columns], previous, lower, upper)
        box.accelerations(previous, lower, upper, self.group.joints)
        return lower, upper

    def parameters(self) -> dict:
        return {"min_position": self._min_position, "max_position": self._max_position,
                "max_velocity": self._max_velocity, "max_acceleration": self._max_acceleration}

    def configure(self, **parameters) -> None:
        unknown = set(parameters) - set(self.parameters())
        if unknown:
            raise UnknownName("parameter of joint_kinematic", sorted(unknown)[0],
                              list(self.parameters()))
        super().configure(**parameters)
        if (self._min_position > self._max_position).any():
            raise InvalidParameter(self.label, "min_position", self._min_position,
                                   "at most max_position")

    def describe(self) -> str:
        return f"group={self.group.name!r}, "
