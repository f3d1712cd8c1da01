"""Viable bounds: how fast the robot may approach a limit or an obstacle and still stop
before it within its acceleration limits, in discrete time.

With the command ``v`` held over each period ``dt`` and braking at ``a`` from one period
to the next, the distance covered until rest is at most
``v^2 / 2a + v dt / 2 + a dt^2 / 8`` (Del Prete, "Joint position and velocity bounds in
discrete-time acceleration/torque control", 2018). The speed towards a limit ``d`` away
is therefore bounded by::

    v <= min(d / dt, max(sqrt(2 a d) - a dt / 2, 0))

and a state that keeps this bound keeps a feasible next cycle: the bound shrinks by at
most ``a dt`` per period. ``a`` is :data:`BRAKING_SHARE` of the acceleration limit, so
that a braking joint keeps some acceleration for the other constraints.
"""

from __future__ import annotations

import numpy as np

BRAKING_SHARE = 0.5
"""Share of the acceleration limit a viable bound plans its braking with."""


def approach_speed(distance, acceleration, time_step: float):
    """The largest speed [rad/s or m/s] towards a limit ``distance`` away [rad or m]
    from which braking at ``acceleration`` [rad/s^2 or m/s^2] (already the share,
    ``inf`` for none) stops before it; negative (move back) past the limit."""
    distance = np.asarray(distance, dtype=float)
    reach = distance / time_step
    with np.errstate(invalid="ignore"):
        braking = np.sqrt(2.0 * acceleration * np.maximum(distance, 0.0)) - (
            0.5 * time_step * acceleration)
    braking = np.where(np.isfinite(braking), np.maximum(braking, 0.0), np.inf)
    return np.minimum(reach, braking)


def joint_box(positions: np.ndarray, previous: np.ndarray, limits,
              time_step: float) -> tuple[np.ndarray, np.ndarray]:
    """Velocity bounds [rad/s or m/s] that keep every joint within its position and speed
    limits (a :class:`~robocop_dsl.safety.limits.JointLimits`) at ``positions``, the
    ``previous`` command [rad/s or m/s] given.

    A joint past a position limit may not go further out, and is driven back as fast as
    its acceleration limit allows from ``previous`` (up to its speed limit). The box
    always holds zero velocity when the joint is inside its limits.
    """
    speed = limits.max_velocity
    share = limits.max_acceleration * BRAKING_SHARE
    step = limits.max_acceleration * time_step
    upper = _side(limits.upper - positions, previous, share, step, speed, time_step)
    lower = -_side(positions - limits.lower, -previous, share, step, speed, time_step)
    crossed = lower > upper
    if crossed.any():   # driven back towards a limit it must brake before: either will do
        lower[crossed], upper[crossed] = upper[crossed], lower[crossed]
    return lower, upper


def _side(distance, previous, share, step, speed, time_step: float) -> np.ndarray:
    """The bound on the speed towards limits ``distance`` away (one side of
    :func:`joint_box`)."""
    bound = approach_speed(distance, share, time_step)
    past = distance < 0.0
    if past.any():
        with np.errstate(invalid="ignore"):
            back = np.fmax(np.maximum(bound, -speed), previous - step)
        bound = np.where(past, np.minimum(back, 0.0), bound)
    return np.clip(bound, -speed, speed)


def distance_rate_bounds(gap: np.ndarray, rows: np.ndarray, acceleration: np.ndarray,
                         time_step: float) -> np.ndarray:
    """Lower bounds [m/s] on the rates of distances ``gap`` [m] above their smallest
    allowed value, so that each pair can still stop before it: the distance's rate
    ``rows @ dq`` can change by at most ``|rows| @ a`` per second under the joints'
    ``acceleration`` limits [rad/s^2 or m/s^2], of which :data:`BRAKING_SHARE` is planned.

    ``-inf`` where no acceleration limit applies (the damper alone then bounds the
    approach)."""
    finite = np.isfinite(acceleration)
    if not finite.any():
        return np.full(len(gap), -np.inf)
    braking = np.abs(rows[:, finite]) @ acceleration[finite] * BRAKING_SHARE
    if not finite.all():
        free = np.abs(rows[:, ~finite]).sum(axis=1) > 1e-12
        braking[free] = np.inf
    return -approach_speed(np.maximum(gap, 0.0), braking, time_step)
