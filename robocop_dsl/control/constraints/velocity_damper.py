"""The velocity damper of collision avoidance: how fast a distance may shrink."""

from __future__ import annotations

import numpy as np

RECOVERY_TIME = 0.05
"""[s] A pair closer than the smallest distance allowed is pushed apart at least as fast
as would remove the overlap in this time..."""
RECOVERY_SPEED = 0.02
"""[m/s] ...up to this speed (the damper's own rate, if faster, still holds)."""


def damper_bounds(damper, rate, damping, time_step: float) -> np.ndarray:
    """Lower bounds of distance rates [m/s] (arrays, or numbers).

    ``damper`` is the damper's bound ``-damping * gap`` [m/s] at ``gap`` [m] above the
    smallest distance allowed (``damping`` [1/s]); ``rate`` is the distance's rate at
    the current velocity [m/s].

    Below the smallest distance (``gap < 0``) the pair is pushed apart at least at
    ``min(-gap / RECOVERY_TIME, RECOVERY_SPEED)``: a face held flat against another
    rocks from corner to corner (the closest points jump), and the damper's slow push
    alone would let it settle up to a millimetre too close. When the closest points
    just jumped and the pair already closes faster than the damper allows, a velocity
    jump would be needed: the bound then only asks to brake to a stop at the smallest
    distance (``rate^2 / (2 gap)`` over one ``time_step`` [s]).
    """
    if not np.count_nonzero(np.less(np.minimum(rate, 0.0), damper)):
        return damper       # no pair closing faster than the damper allows, none too close
    braking = np.less(rate, damper)
    overlapping = np.greater(damper, 0.0)
    gap = np.divide(damper, -damping)
    recovery = np.minimum(-gap / RECOVERY_TIME, RECOVERY_SPEED)
    bound = np.where(overlapping, np.maximum(damper, recovery), damper)
    braking &= gap > 0.0
    stop = rate + time_step * rate * rate / (2.0 * np.where(braking, gap, 1.0))
    return np.where(braking, np.minimum(bound, stop), bound)
