"""The ``none`` interpolator: the reference is the target itself."""

from __future__ import annotations

import numpy as np

from .base import Interpolator


class NoInterpolator(Interpolator):
    """Passes the target through; finished at once."""

    kind = "none"
    passthrough = True

    def start(self) -> None:
        """Nothing to plan."""

    def step(self) -> tuple[np.ndarray, np.ndarray]:
        self.position = self.target
        self.velocity = np.zeros(self.dimension)
        return self.position, self.velocity

    @property
    def finished(self) -> bool:
        return True
