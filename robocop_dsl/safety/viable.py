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
HARD_BRAKING_SHARE = 0.8
"""Share of the acceleration limit a speed already above the viable bound brakes at
(the rest is left to the distance's curvature and the other constraints)."""


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


def viable_speed(distance, speed, acceleration, time_step: float):
    """The bound [rad/s or m/s] on the speed towards a limit ``distance`` away, the
    current ``speed`` towards it given: :func:`approach_speed` at :data:`BRAKING_SHARE`
    of ``acceleration``. A speed already above that bound (a limit that came within
    reach while moving fast) is only asked to brake at :data:`HARD_BRAKING_SHARE` of
    ``acceleration``, as long as that still stops before the limit; otherwise the
    share's bound stands, and the cycle relaxes the acceleration limit."""
    bound = approach_speed(distance, acceleration * BRAKING_SHARE, time_step)
    hard = acceleration * HARD_BRAKING_SHARE
    full = approach_speed(distance, hard, time_step)
    with np.errstate(invalid="ignore"):
        braked = np.minimum(speed - hard * time_step, full)
    return np.where(speed > bound, np.fmax(bound, braked), bound)


def distance_rate_bounds(gap: np.ndarray, rows: np.ndarray, rate: np.ndarray,
                         acceleration: np.ndarray, time_step: float) -> np.ndarray:
    """Lower bounds [m/s] on the rates of distances ``gap`` [m] above their smallest
    allowed value, their current ``rate`` [m/s] given, so that each pair can still stop
    before it (:func:`viable_speed`): the distance's rate ``rows @ dq`` can change by at
    most ``|rows| @ a`` per second under the joints' ``acceleration`` limits
    [rad/s^2 or m/s^2].

    ``-inf`` where no acceleration limit applies (the damper alone then bounds the
    approach)."""
    finite = np.isfinite(acceleration)
    if not finite.any():
        return np.full(len(gap), -np.inf)
    capacity = np.abs(rows[:, finite]) @ acceleration[finite]
    if not finite.all():
        free = np.abs(rows[:, ~finite]).sum(axis=1) > 1e-12
        capacity[free] = np.inf
    return -viable_speed(np.maximum(gap, 0.0), -rate, capacity, time_step)
