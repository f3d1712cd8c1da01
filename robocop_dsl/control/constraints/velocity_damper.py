"""The velocity damper of collision avoidance: how fast a distance may shrink."""

from __future__ import annotations

import numpy as np


def damper_bounds(damper, rate, damping, time_step: float) -> np.ndarray:
    """Lower bounds of distance rates [m/s] (arrays, or numbers).

    ``damper`` is the damper's bound ``-damping * gap`` [m/s] at ``gap`` [m] above the
    smallest distance allowed (``damping`` [1/s]); ``rate`` is the distance's rate at
    the current velocity [m/s]. When the closest points just jumped (a face of one shape
    came parallel to the other: the distance is not smooth there) and the pair already
    closes faster than the damper allows, a velocity jump would be needed: the bound
    then only asks to brake to a stop at the smallest distance (``rate^2 / (2 gap)``
    over one ``time_step`` [s]).
    """
    braking = np.less(rate, damper)
    if not np.count_nonzero(braking):
        return damper
    gap = np.divide(damper, -damping)
    braking &= gap > 0.0
    stop = rate + time_step * rate * rate / (2.0 * np.where(braking, gap, 1.0))
    return np.where(braking, np.minimum(damper, stop), damper)
