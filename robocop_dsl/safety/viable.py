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
SPEED_TOLERANCE = 1e-9
"""A speed within this of its viable bound [rad/s or m/s] is at it, not above it."""
HARD_BRAKING_SHARE = 0.8
"""Share of the acceleration limit a speed already above the viable bound brakes at
(the rest is left to the distance's curvature and the other constraints)."""


def approach_speed(distance, acceleration, time_step: float):
    """The largest speed [rad/s or m/s] towards a limit ``distance`` away [rad or m]
    from which braking at ``acceleration`` [rad/s^2 or m/s^2] (already the share,
    ``inf`` for none) stops before it; negative (move back) past the limit."""
    scalar = np.ndim(distance) == np.ndim(acceleration) == 0
    distance, acceleration = _arrays(distance, acceleration)
    unlimited = ~np.isfinite(acceleration)
    bound = _approach(distance, np.where(unlimited, 0.0, acceleration), time_step)
    bound[unlimited] = (distance / time_step)[unlimited]
    return float(bound[0]) if scalar else bound


def viable_speed(distance, speed, acceleration, time_step: float):
    """The bound [rad/s or m/s] on the speed towards a limit ``distance`` away, the
    current ``speed`` towards it given: :func:`approach_speed` at :data:`BRAKING_SHARE`
    of ``acceleration``. A speed already above that bound (a limit that came within
    reach while moving fast) is only asked to brake at :data:`HARD_BRAKING_SHARE` of
    ``acceleration``, as long as that still stops before the limit; otherwise the
    share's bound stands, and the cycle relaxes the acceleration limit."""
    scalar = np.ndim(distance) == np.ndim(speed) == np.ndim(acceleration) == 0
    distance, speed, acceleration = _arrays(distance, speed, acceleration)
    unlimited = ~np.isfinite(acceleration)
    bound = _viable(distance, speed, np.where(unlimited, 0.0, acceleration), time_step)
    bound[unlimited] = (distance / time_step)[unlimited]
    return float(bound[0]) if scalar else bound


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
    if finite.all():
        capacity = np.abs(rows) @ acceleration
        bound = _viable(np.maximum(gap, 0.0), np.negative(rate), capacity, time_step)
        return np.negative(bound, out=bound)
    if not finite.any():
        return np.full(len(gap), -np.inf)
    capacity = np.abs(rows[:, finite]) @ acceleration[finite]
    capacity[np.abs(rows[:, ~finite]).sum(axis=1) > 1e-12] = np.inf
    return -viable_speed(np.maximum(gap, 0.0), -rate, capacity, time_step)


def _arrays(*values) -> list[np.ndarray]:
    """``values`` as float arrays of one shape, at least one-dimensional (copies)."""
    return [np.array(value) for value in np.broadcast_arrays(
        *(np.atleast_1d(np.asarray(value, dtype=float)) for value in values))]


def _approach(distance: np.ndarray, acceleration: np.ndarray, time_step: float):
    """:func:`approach_speed` of arrays, every acceleration finite (a new array)."""
    braking = np.maximum(distance, 0.0)
    braking *= 2.0 * acceleration
    np.sqrt(braking, out=braking)
    braking -= 0.5 * time_step * acceleration
    np.maximum(braking, 0.0, out=braking)
    return np.minimum(distance / time_step, braking, out=braking)


def _viable(distance: np.ndarray, speed: np.ndarray, acceleration: np.ndarray,
            time_step: float) -> np.ndarray:
    """:func:`viable_speed` of arrays, every acceleration finite (a new array)."""
    bound = _approach(distance, acceleration * BRAKING_SHARE, time_step)
    fast = np.greater(speed, bound + SPEED_TOLERANCE)
    if np.count_nonzero(fast):
        fast = np.flatnonzero(fast)
        hard = acceleration[fast] * HARD_BRAKING_SHARE
        braked = np.minimum(speed[fast] - hard * time_step,
                            _approach(distance[fast], hard, time_step))
        bound[fast] = np.maximum(bound[fast], braked)
    return bound
