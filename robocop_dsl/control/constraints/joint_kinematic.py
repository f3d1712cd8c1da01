"""The ``joint_kinematic`` constraint: position, velocity and acceleration limits."""

from __future__ import annotations

import numpy as np

from ..exceptions import InvalidParameter, UnknownName
from ..parameters import vector_parameter
from ..state import ControlState
from .base import Constraint


class JointKinematicConstraint(Constraint):
    """Joint limits of a group turned into bounds on the next velocity command.

    For each joint, with ``dt`` the time step and ``prev`` the previous command:

    - velocity: ``|dq| <= max_velocity``;
    - acceleration: ``|dq - prev| <= max_acceleration * dt``;
    - position: ``dq`` no larger than the speed from which the joint can still stop
      before ``max_position`` braking at ``max_acceleration`` in steps of ``dt`` (and
      at least ``(max_position - q) / dt``), and likewise towards ``min_position``.

    A joint outside its position range is driven back as fast as its velocity limit
    allows. When the acceleration bound conflicts with the others (e.g. after the
    state jumped), the velocity closest to ``prev`` within the others is taken.

    Args:
        name: The constraint's name.
        state: The controller's state.
        group: The joint group (inside the controlled group).
        min_position: Lower positions [rad or m]; default the URDF's.
        max_position: Upper positions [rad or m]; default the URDF's.
        max_velocity: Speed limits [rad/s or m/s]; default the URDF's.
        max_acceleration: Acceleration limits [rad/s^2 or m/s^2]; default the world's
            (``inf`` when unknown: no acceleration bound).
    """

    kind = "joint_kinematic"

    def __init__(self, name: str, state: ControlState, group: str, *, min_position=None,
                 max_position=None, max_velocity=None, max_acceleration=None):
        super().__init__(name, state)
        self.group, self.box_columns = state.group_columns(group)
        self._positions = state.q_indices[self.box_columns]
        self._jacobian = np.eye(state.dofs)[self.box_columns]
        group_ = self.group
        self.min_position = group_.lower if min_position is None else min_position
        self.max_position = group_.upper if max_position is None else max_position
        self.max_velocity = group_.max_velocity if max_velocity is None else max_velocity
        acceleration = getattr(group_, "max_acceleration", None)
        self.max_acceleration = (np.inf if acceleration is None else acceleration) \
            if max_acceleration is None else max_acceleration

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

    @property
    def max_position(self) -> np.ndarray:
        """Upper position limits [rad or m]."""
        return self._max_position

    @max_position.setter
    def max_position(self, value) -> None:
        self._max_position = self._vector("max_position", value)

    @property
    def max_velocity(self) -> np.ndarray:
        """Speed limits [rad/s or m/s]."""
        return self._max_velocity

    @max_velocity.setter
    def max_velocity(self, value) -> None:
        self._max_velocity = self._vector("max_velocity", value, minimum=0.0)

    @property
    def max_acceleration(self) -> np.ndarray:
        """Acceleration limits [rad/s^2 or m/s^2]."""
        return self._max_acceleration

    @max_acceleration.setter
    def max_acceleration(self, value) -> None:
        self._max_acceleration = self._vector("max_acceleration", value, minimum=0.0)

    @property
    def rows(self) -> int:
        return len(self.box_columns)

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return self._jacobian

    def compute_bounds(self, state: ControlState) -> tuple[np.ndarray, np.ndarray]:
        dt = state.time_step
        q = state.q[self._positions]
        speed = self._max_velocity
        upper = np.minimum(speed, self._position_speed(self._max_position - q, dt))
        lower = np.maximum(-speed, -self._position_speed(q - self._min_position, dt))
        upper = np.maximum(upper, -speed)
        lower = np.minimum(lower, speed)
        previous = state.previous_command[self.box_columns]
        step = self._max_acceleration * dt
        accelerated_lower = np.maximum(lower, previous - step)
        accelerated_upper = np.minimum(upper, previous + step)
        conflict = accelerated_lower > accelerated_upper
        if conflict.any():
            closest = np.clip(previous, lower, upper)
            accelerated_lower[conflict] = closest[conflict]
            accelerated_upper[conflict] = closest[conflict]
        return accelerated_lower, accelerated_upper

    def _position_speed(self, distance: np.ndarray, dt: float) -> np.ndarray:
        """Largest speed towards a limit ``distance`` away that can still stop before it."""
        acceleration = self._max_acceleration
        speed = distance / dt
        braking = np.isfinite(acceleration) & (distance > 0.0)
        if braking.any():
            step = acceleration[braking] * dt
            steps = distance[braking] / (step * dt)
            whole = np.floor((np.sqrt(1.0 + 8.0 * steps) - 1.0) / 2.0)
            speed[braking] = step * (steps / (whole + 1.0) + whole / 2.0)
        return speed

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
