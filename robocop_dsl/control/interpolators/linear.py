"""The ``linear`` interpolator: constant velocity over a duration."""

from __future__ import annotations

from .timed import TimedInterpolator


class LinearInterpolator(TimedInterpolator):
    """``s(tau) = tau``: constant velocity, velocity steps at both ends."""

    kind = "linear"

    def profile(self, tau: float) -> tuple[float, float]:
        return tau, 1.0
