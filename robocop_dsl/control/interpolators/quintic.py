"""The ``quintic`` interpolator: zero velocity and acceleration at both ends."""

from __future__ import annotations

from .timed import TimedInterpolator


class QuinticInterpolator(TimedInterpolator):
    """``s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5``: rest-to-rest, smooth acceleration."""

    kind = "quintic"

    def profile(self, tau: float) -> tuple[float, float]:
        tau2 = tau * tau
        return tau2 * tau * (10.0 - 15.0 * tau + 6.0 * tau2), 30.0 * tau2 * (1.0 - tau) ** 2
