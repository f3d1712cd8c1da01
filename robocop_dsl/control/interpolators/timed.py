"""Base of the fixed-duration interpolators: ``x = x0 + s(t / T) (target - x0)``."""

from __future__ import annotations

from abc import abstractmethod

import numpy as np

from ..parameters import scalar_parameter
from .base import Interpolator


class TimedInterpolator(Interpolator):
    """Moves from the start to the target along a time-scaling profile ``s``.

    The target is read every step, so a moving target is followed; after ``duration``
    the reference is the target.

    Args:
        duration: Time to reach the target [s].
    """

    def __init__(self, duration: float):
        super().__init__()
        self.duration = scalar_parameter(self.kind, "duration", duration, minimum=0.0,
                                         strict=True)
        self.elapsed = 0.0
        self.start_position = np.zeros(0)

    def start(self) -> None:
        self.elapsed = 0.0
        self.start_position = self.position.copy()

    def step(self) -> tuple[np.ndarray, np.ndarray]:
        self.elapsed = min(self.elapsed + self.time_step, self.duration)
        s, rate = self.profile(self.elapsed / self.duration)
        span = self.target - self.start_position
        self.position = self.start_position + s * span
        self.velocity = (rate / self.duration) * span
        return self.position, self.velocity

    @abstractmethod
    def profile(self, tau: float) -> tuple[float, float]:
        """Time scaling ``s(tau)`` and ``ds/dtau`` for ``tau`` in [0, 1]."""

    @property
    def finished(self) -> bool:
        return self.elapsed >= self.duration

    def parameters(self) -> dict:
        return {"duration": self.duration}
