"""The joint limits a controller keeps: one table per controlled group, the stricter of
the world's (URDF) and of every enabled ``joint_kinematic`` constraint."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class JointLimits:
    """Per dof of the controlled group, in its order (``inf`` where unlimited).

    Attributes:
        lower: Lowest positions [rad or m].
        upper: Highest positions [rad or m].
        max_velocity: Speed limits [rad/s or m/s].
        max_acceleration: Acceleration limits [rad/s^2 or m/s^2].
        owners: Per dof, the name of what sets its acceleration limit (a
            ``joint_kinematic`` constraint's label, or ``"the world's limits"``).
        conflict: Why the position limits leave a joint no position at all (a lowest
            above a highest), else ``None``.
    """

    lower: np.ndarray
    upper: np.ndarray
    max_velocity: np.ndarray
    max_acceleration: np.ndarray
    owners: tuple[str, ...]
    conflict: str | None = None


WORLD = "the world's limits"


def joint_limits(group, constraints) -> JointLimits:
    """The table of ``group`` (the controller's :class:`~robocop_dsl.world.JointGroup`)
    narrowed by ``constraints``: the enabled constraints that have ``joint_limits()``
    (columns and limits, see
    :meth:`~robocop_dsl.control.constraints.JointKinematicConstraint.joint_limits`)."""
    lower = np.array(group.lower, dtype=float)
    upper = np.array(group.upper, dtype=float)
    velocity = np.array(group.max_velocity, dtype=float)
    acceleration = np.array(group.max_acceleration, dtype=float)
    owners = [WORLD] * len(lower)
    for constraint in constraints:
        columns, low, high, speed, accel = constraint.joint_limits()
        lower[columns] = np.maximum(lower[columns], low)
        upper[columns] = np.minimum(upper[columns], high)
        velocity[columns] = np.minimum(velocity[columns], speed)
        columns, accel = np.asarray(columns), np.asarray(accel, dtype=float)
        stricter = np.flatnonzero(accel < acceleration[columns])
        if stricter.size:
            acceleration[columns[stricter]] = accel[stricter]
            label = constraint.label
            for column in columns[stricter].tolist():
                owners[column] = label
    crossed = np.flatnonzero(lower > upper)
    conflict = None
    if crossed.size:
        joint = crossed[0]
        conflict = (f"the position limits of {group.joints[joint]} leave it no position "
                    f"(lowest {lower[joint]:g} above highest {upper[joint]:g})")
    return JointLimits(lower, upper, velocity, acceleration, tuple(owners), conflict)
