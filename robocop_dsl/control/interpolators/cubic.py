"""The ``cubic`` interpolator: zero velocity at both ends."""

from __future__ import annotations

from .timed import TimedInterpolator


class CubicInterpolator(TimedInterpolator):
    """``s(tau) = 3 tau^2 - 2 tau^3``: starts and ends at rest."""

    kind = "cubic"

    def profile(self, tau: float) -> tuple[float, float]:
        return tau * tau * (3.0 - 2.0 * tau), 6.0 * tau * (1.0 - tau)
