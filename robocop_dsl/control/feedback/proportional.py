"""The ``proportional`` feedback loop."""

from __future__ import annotations

import numpy as np

from ..parameters import vector_parameter
from .base import FeedbackLoop


class ProportionalFeedback(FeedbackLoop):
    """``velocity = gain * error``.

    Args:
        gain: Scalar or per-axis gain [1/s], non-negative.
    """

    kind = "proportional"

    def __init__(self, gain=1.0):
        super().__init__()
        self._raw = gain
        self._gain = vector_parameter(self.kind, "gain", gain, np.size(gain), minimum=0.0)
        if np.ndim(gain) == 0:
            self._gain = float(gain)

    def validate(self) -> None:
        if np.ndim(self._gain) != 0:
            self._gain = vector_parameter(self.kind, "gain", self._gain, self.dimension,
                                          minimum=0.0)

    def compute(self, error: np.ndarray) -> np.ndarray:
        return self._gain * error

    @property
    def gain(self):
        return self._gain

    @gain.setter
    def gain(self, value) -> None:
        if np.ndim(value) == 0:
            self._gain = float(vector_parameter(self.kind, "gain", value, 1, minimum=0.0)[0])
        else:
            self._gain = vector_parameter(self.kind, "gain", value, self.dimension or np.size(value),
                                          minimum=0.0)

    def parameters(self) -> dict:
        return {"gain": self._gain}
