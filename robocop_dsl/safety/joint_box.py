"""The joint limits table as velocity bounds, every cycle: viable bounds towards the
position limits (:mod:`~robocop_dsl.safety.viable`), the speed limits, then the
acceleration limits around the previous command."""

from __future__ import annotations

import numpy as np

from .limits import JointLimits
from .relaxation import acceleration_box
from .viable import BRAKING_SHARE, _viable, viable_speed


class JointBox:
    """The velocity box of a :class:`~robocop_dsl.safety.limits.JointLimits` table at a
    control period, computed in place from one cycle to the next.

    Both sides are computed as one stacked vector (the speed towards each upper limit,
    then towards each lower one); the common case (no joint past a limit, none faster
    than its viable bound) costs a few vector operations.

    Args:
        limits: The table.
        time_step: The control period [s].
    """

    def __init__(self, limits: JointLimits, time_step: float):
        n = len(limits.lower)
        self.limits = limits
        self.time_step = time_step
        self._n = n
        self._acceleration = np.concatenate((limits.max_acceleration,) * 2)
        self._speed = np.concatenate((limits.max_velocity,) * 2)
        self._negative_speed = -self._speed
        self._step = limits.max_acceleration * time_step
        self._rate = 1.0 / time_step
        finite = np.isfinite(self._acceleration)
        share = np.where(finite, self._acceleration, 0.0) * BRAKING_SHARE
        self._braking = (2.0 * share, 0.5 * time_step * share) if finite.any() else None
        self._unlimited = np.flatnonzero(~finite)
        limit = np.concatenate((limits.upper, -np.asarray(limits.lower)))
        reach = np.finfo(float).max * time_step / 4     # farther: bounds would overflow
        self._limit = np.where(np.isfinite(limit), np.clip(limit, -reach, reach), limit)
        self._distance = np.zeros(2 * n)
        self._toward = np.zeros(2 * n)
        self._bound = np.zeros(2 * n)
        self._scratch = np.zeros(2 * n)
        self._mask = np.zeros(2 * n, dtype=bool)

    def write(self, positions: np.ndarray, previous: np.ndarray, lower: np.ndarray,
              upper: np.ndarray) -> None:
        """Write into ``lower`` and ``upper`` [rad/s or m/s] the bounds that keep every
        joint within its position and speed limits at ``positions``, the ``previous``
        command [rad/s or m/s] given.

        Towards a limit, the speed is bounded by
        :func:`~robocop_dsl.safety.viable.viable_speed`. A joint past a position limit
        may not go further out, and is driven back as fast as its acceleration limit
        allows from ``previous`` (up to its speed limit). The box holds zero velocity
        for every joint inside its limits.
        """
        n = self._n
        distance, toward, bound = self._distance, self._toward, self._bound
        np.subtract(self._limit[:n], positions, out=distance[:n])
        np.add(self._limit[n:], positions, out=distance[n:])
        toward[:n] = previous
        np.negative(previous, out=toward[n:])
        np.multiply(distance, self._rate, out=bound)
        if self._braking is not None:
            two_a, half_step = self._braking
            braking = np.maximum(distance, 0.0, out=self._scratch)
            np.multiply(braking, two_a, out=braking)
            np.sqrt(braking, out=braking)
            np.subtract(braking, half_step, out=braking)
            if self._unlimited.size:
                braking[self._unlimited] = np.inf
            np.minimum(bound, braking, out=bound)
            np.maximum(bound, 0.0, out=bound)   # the braking bound is never negative
        mask = self._mask
        if not (np.count_nonzero(np.less(distance, 0.0, out=mask))
                or self._braking is not None
                and np.count_nonzero(np.less(bound, toward, out=mask))):
            np.minimum(bound, self._speed, out=bound)   # inside the limits, none too fast
            upper[:] = bound[:n]
            np.negative(bound[n:], out=lower)
            return
        self._slow_side(distance, toward, bound)
        np.minimum(bound, self._speed, out=bound)
        np.maximum(bound, self._negative_speed, out=bound)
        upper[:] = bound[:n]
        np.negative(bound[n:], out=lower)
        crossed = np.greater(lower, upper, out=self._mask[:n])
        if np.count_nonzero(crossed):   # back towards a limit it must brake before: either
            crossed = np.flatnonzero(crossed)
            lower[crossed], upper[crossed] = upper[crossed], lower[crossed]

    def _slow_side(self, distance: np.ndarray, toward: np.ndarray, bound: np.ndarray) -> None:
        """The bounds of the sides a joint approaches faster than its viable bound, or
        whose limit it is past."""
        if self._braking is not None:
            fast = np.greater(toward, bound, out=self._mask)
            if np.count_nonzero(fast):
                fast = np.flatnonzero(fast)
                viable = viable_speed if self._unlimited.size else _viable
                bound[fast] = viable(distance[fast], toward[fast], self._acceleration[fast],
                                     self.time_step)
        past = np.less(distance, 0.0, out=self._mask)
        if np.count_nonzero(past):
            past = np.flatnonzero(past)
            bound[past] = self._driven_back(distance[past] * self._rate, toward[past], past)

    def _driven_back(self, bound: np.ndarray, toward: np.ndarray, past: np.ndarray):
        """The bounds of the sides ``past`` whose limit the joint is past (``bound``:
        their distance over a period, negative): no further out, back as fast as the
        acceleration allows (up to the speed limit)."""
        with np.errstate(invalid="ignore"):
            back = np.fmax(np.maximum(bound, -self._speed[past]),
                           toward - self._acceleration[past] * self.time_step)
        return np.minimum(back, 0.0)

    def accelerations(self, previous: np.ndarray, lower: np.ndarray, upper: np.ndarray,
                      joints) -> list:
        """Meet the box ``[lower, upper]`` with the acceleration limits around
        ``previous``, in place; where they do not meet, see
        :func:`~robocop_dsl.safety.relaxation.acceleration_box`. Returns the
        relaxations."""
        n = self._n
        low = np.subtract(previous, self._step, out=self._scratch[:n])
        high = np.add(previous, self._step, out=self._scratch[n:])
        if (np.count_nonzero(np.greater(low, upper, out=self._mask[:n]))
                or np.count_nonzero(np.less(high, lower, out=self._mask[n:]))):
            return acceleration_box(previous, self.limits, self.time_step, lower, upper,
                                    joints)
        np.maximum(lower, low, out=lower)
        np.minimum(upper, high, out=upper)
        return []
