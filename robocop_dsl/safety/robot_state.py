"""A checked robot: the state a driver reports, validated every cycle before the
controller sees it.

A state is refused when, for a joint of the controlled group,

- a position coordinate or a velocity is not finite;
- the position is past the URDF's limit by more than ``state_tolerance`` [rad] (a
  prismatic joint: :data:`PRISMATIC_SHARE` of it, in metres); continuous joints have
  no position limit;
- the speed is above :data:`VELOCITY_MARGIN` times the URDF's limit.

The limits are stacked once per joint group; a cycle's check is a few vectorised
comparisons, and the message naming the joint, its value and the limit is only built
for a refused state.
"""

from __future__ import annotations

import numpy as np

from ..diagnostics import RobocopError
from ..world.processors import option_default

VELOCITY_MARGIN = 1.5
"""How many times its URDF speed limit a joint may be reported moving at."""
PRISMATIC_SHARE = 0.1
"""A prismatic joint's position tolerance [m] per radian of ``state_tolerance``."""
DEFAULT_TOLERANCE = option_default("qp_controller", "state_tolerance")
"""The ``state_tolerance`` of a ``qp_controller`` that gives none [rad]."""


class RobotStateError(RobocopError):
    """A state the robot cannot be in: a driver's fault."""


class RobotStateCheck:
    """Validates the driver's state of a joint group.

    Args:
        world: The world (its model and URDF limits).
        joint_group: The group (or joint) the driver reports.
        state_tolerance: How far past its URDF position limits a joint may be reported
            [rad]; a prismatic joint gets :data:`PRISMATIC_SHARE` of it [m].
    """

    def __init__(self, world, joint_group: str, state_tolerance: float = DEFAULT_TOLERANCE):
        group = world.joint_group(joint_group)
        self.state_tolerance = float(state_tolerance)
        self._q_indices, self._v_indices = group.q_indices, group.v_indices
        model = world.model
        joints = [model.joints[model.getJointId(name)] for name in group.joints]
        self._coordinate_joint = np.repeat(group.joints, [j.nq for j in joints])
        self._dof_joint = np.repeat(group.joints, [j.nv for j in joints])
        prismatic = np.repeat([world.joint(n).type == "prismatic" for n in group.joints],
                              [j.nv for j in joints])
        self._unit = np.where(prismatic, "m", "rad")
        self._tolerance = np.where(prismatic, PRISMATIC_SHARE, 1.0) * self.state_tolerance
        coordinates = np.concatenate([np.arange(j.idx_q, j.idx_q + j.nv) if j.nq == j.nv
                                      else np.full(j.nv, -1) for j in joints] or [[]])
        self._limited = np.flatnonzero((coordinates >= 0) & (
            np.isfinite(group.lower) | np.isfinite(group.upper)))
        self._limited_q = coordinates[self._limited].astype(int)
        self._lower, self._upper = group.lower[self._limited], group.upper[self._limited]
        self._low = self._lower - self._tolerance[self._limited]
        self._high = self._upper + self._tolerance[self._limited]
        self._max_velocity = np.asarray(group.max_velocity, dtype=float)
        self._fastest = VELOCITY_MARGIN * self._max_velocity

    def __repr__(self) -> str:
        return (f"RobotStateCheck({len(self._dof_joint)} dofs, "
                f"state_tolerance={self.state_tolerance:g} rad)")

    @classmethod
    def for_controller(cls, controller) -> "RobotStateCheck":
        """The check of ``controller``'s joint group with the ``state_tolerance`` of the
        world's ``qp_controller`` on that group (the smallest when several are)."""
        group = controller.joint_group.name
        given = [p.run_options.get("state_tolerance", DEFAULT_TOLERANCE)
                 for p in controller.world.processors.values()
                 if p.type == "qp_controller" and p.options.get("joint_group") == group]
        return cls(controller.world, group, min(given, default=DEFAULT_TOLERANCE))

    def check(self, q: np.ndarray, v: np.ndarray) -> str | None:
        """``None`` when the world's ``q`` (nq) and ``v`` (nv) hold a state the group's
        joints can be in, else what is wrong with it."""
        position, velocity = q[self._q_indices], v[self._v_indices]
        limited = q[self._limited_q]
        if (np.isfinite(position).all() and np.isfinite(velocity).all()
                and (limited >= self._low).all() and (limited <= self._high).all()
                and (np.abs(velocity) <= self._fastest).all()):
            return None
        return self._explain(position, velocity, limited)

    def require(self, q: np.ndarray, v: np.ndarray) -> None:
        """Raise :class:`RobotStateError` when :meth:`check` refuses the state."""
        problem = self.check(q, v)
        if problem is not None:
            raise RobotStateError(problem)

    def _explain(self, position, velocity, limited) -> str:
        """What is wrong with the first joint, in the group's order, that is wrong."""
        if not np.isfinite(position).all():
            at = int(np.flatnonzero(~np.isfinite(position))[0])
            return (f"the robot reports joint '{self._coordinate_joint[at]}' at a "
                    f"non-finite position ({position[at]})")
        if not np.isfinite(velocity).all():
            at = int(np.flatnonzero(~np.isfinite(velocity))[0])
            return (f"the robot reports joint '{self._dof_joint[at]}' moving at a "
                    f"non-finite velocity ({velocity[at]})")
        past = np.flatnonzero((limited < self._low) | (limited > self._high))
        if past.size:
            return self._past_limit(int(past[0]), limited)
        at = int(np.flatnonzero(np.abs(velocity) > self._fastest)[0])
        unit = self._unit[at]
        return (f"the robot reports joint '{self._dof_joint[at]}' moving at "
                f"{velocity[at]:.4g} {unit}/s, above {VELOCITY_MARGIN:g} times its URDF "
                f"velocity limit {self._max_velocity[at]:.4g} {unit}/s")

    def _past_limit(self, index: int, limited) -> str:
        dof = self._limited[index]
        value, unit, tolerance = limited[index], self._unit[dof], self._tolerance[dof]
        side, limit = (("lower", self._lower[index]) if value < self._low[index]
                       else ("upper", self._upper[index]))
        return (f"the robot reports joint '{self._dof_joint[dof]}' at {value:.4g} {unit}, "
                f"past its URDF {side} limit {limit:.4g} {unit} by {abs(value - limit):.3g} "
                f"{unit} (state_tolerance {tolerance:g} {unit})")
