"""The ``joint_kinematic`` constraint: position, velocity and acceleration limits."""

from __future__ import annotations

import numpy as np

from ..exceptions import InvalidParameter, UnknownName
from ..parameters import vector_parameter
from ..state import ControlState
from .base import Constraint

BRAKING_SHARE = 0.5
"""Share of ``max_acceleration`` used to plan braking before a position limit."""


class JointKinematicConstraint(Constraint):
    """Joint limits of a group turned into bounds on the next velocity command.

    For each joint, with ``dt`` the time step and ``prev`` the previous command:

    - velocity: ``|dq| <= max_velocity``;
    - acceleration: ``|dq - prev| <= max_acceleration * dt``;
    - position: ``dq`` at most ``(max_position - q) / dt`` and at most the speed from
      which the joint can still stop before ``max_position`` braking at half of
      ``max_acceleration`` in steps of ``dt``; likewise towards ``min_position``.

    Velocity and acceleration limits never exceed the world's (the URDF's): a larger
    value given here is lowered to it. A continuous joint has no position limit by
    default; its position is its angle in (-pi, pi]. A joint outside its position
    range is driven back as fast as its velocity limit allows. When the acceleration bound conflicts with the others (e.g. after the
    state jumped), the velocity closest to ``prev`` within the others is taken.

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
        self._time_step = None
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
        self._time_step = None

    @property
    def max_position(self) -> np.ndarray:
        """Upper position limits [rad or m]."""
        return self._max_position

    @max_position.setter
    def max_position(self, value) -> None:
        self._max_position = self._vector("max_position", value)
        self._time_step = None

    @property
    def max_velocity(self) -> np.ndarray:
        """Speed limits [rad/s or m/s], the world's where those are lower."""
        return self._max_velocity

    @max_velocity.setter
    def max_velocity(self, value) -> None:
        self._max_velocity = np.minimum(self._vector("max_velocity", value, minimum=0.0),
                                        self._velocity_bound)
        self._time_step = None

    @property
    def max_acceleration(self) -> np.ndarray:
        """Acceleration limits [rad/s^2 or m/s^2], the world's where those are lower."""
        return self._max_acceleration

    @max_acceleration.setter
    def max_acceleration(self, value) -> None:
        self._max_acceleration = np.minimum(
            self._vector("max_acceleration", value, minimum=0.0), self._acceleration_bound)
        self._time_step = None

    @property
    def rows(self) -> int:
        return len(self.box_columns)

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return self._jacobian

    def compute_bounds(self, state: ControlState) -> tuple[np.ndarray, np.ndarray]:
        dt = state.time_step
        if dt != self._time_step:
            self._prepare(dt)
        # Upper bounds first, then the negated lower bounds: one vector for both sides.
        signs, zeros = self._signs, self._zeros
        distance = signs * state.group_positions[self._positions]
        np.subtract(self._limits, distance, out=distance)
        reach = distance * self._rate
        if self._braking is not None:
            two_a, half_step, finite = self._braking
            braking = np.maximum(distance, zeros, out=distance)
            np.multiply(braking, two_a, out=braking)
            np.sqrt(braking, out=braking)
            np.subtract(braking, half_step, out=braking)
            np.maximum(braking, zeros, out=braking)
            if finite is not None:
                braking[~finite] = np.inf
            np.minimum(reach, braking, out=reach)
        np.maximum(reach, self._negative_speed, out=reach)
        np.minimum(reach, self._speed, out=reach)
        bound = signs * state.previous_command[self._columns]
        np.add(bound, self._steps, out=bound)
        np.minimum(reach, bound, out=bound)
        count = self._count
        upper, lower = bound[:count], np.negative(bound[count:])
        conflict = np.greater(lower, upper)
        if np.count_nonzero(conflict):
            previous = state.previous_command[self.box_columns]
            closest = np.clip(previous, -reach[count:], reach[:count])
            lower[conflict] = upper[conflict] = closest[conflict]
        return lower, upper

    def _prepare(self, dt: float) -> None:
        """Precompute stacked limits and the braking terms ``2 a`` and ``a dt / 2``.

        Braking at ``a`` in steps of ``dt`` from speed ``v`` covers at most
        ``v^2 / 2a + v dt / 2 + a dt^2 / 8``, so the speed towards a limit ``d`` away
        is bounded by ``max(sqrt(2 a d) - a dt / 2, 0)``; this bound stays feasible
        from one cycle to the next under the acceleration limit. ``a`` is
        :data:`BRAKING_SHARE` of ``max_acceleration``, so a braking joint keeps some
        freedom for the other constraints.
        """
        count = len(self.box_columns)
        acceleration = np.tile(self._max_acceleration, 2)
        finite = np.isfinite(acceleration)
        self._time_step = dt
        self._count = count
        self._positions = np.tile(self.box_columns, 2)
        self._columns = np.tile(self.box_columns, 2)
        self._signs = np.concatenate((np.ones(count), -np.ones(count)))
        self._zeros = np.zeros(2 * count)
        self._rate = np.full(2 * count, 1.0 / dt)
        self._limits = np.concatenate((self._max_position, -self._min_position))
        self._speed = np.tile(self._max_velocity, 2)
        self._negative_speed = -self._speed
        self._steps = acceleration * dt
        if not finite.any():
            self._braking = None
            return
        acceleration = np.where(finite, acceleration, 0.0) * BRAKING_SHARE
        self._braking = (2.0 * acceleration, 0.5 * dt * acceleration,
                         None if finite.all() else finite)

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
