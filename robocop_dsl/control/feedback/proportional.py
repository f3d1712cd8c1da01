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
        self._gain = self._checked(gain, np.size(gain))
        self._broadcast()

    def _checked(self, value, size: int):
        array = vector_parameter(self.kind, "gain", value, size, minimum=0.0)
        return float(array[0]) if np.ndim(value) == 0 else array

    def validate(self) -> None:
        if np.ndim(self._gain) != 0:
            self._gain = self._checked(self._gain, self.dimension)
        self._broadcast()

    def _broadcast(self) -> None:
        """One gain per axis once the dimension is known: multiplying two arrays is
        cheaper than multiplying an array by a Python float."""
        gain = self._gain
        scalar = np.ndim(gain) == 0 and self.dimension
        self._gains = np.full(self.dimension, gain) if scalar else gain

    def compute(self, error: np.ndarray) -> np.ndarray:
        return self._gains * error

    @property
    def gain(self):
        return self._gain

    @gain.setter
    def gain(self, value) -> None:
        size = 1 if np.ndim(value) == 0 else (self.dimension or np.size(value))
        self._gain = self._checked(value, size)
        self._broadcast()

    def parameters(self) -> dict:
        return {"gain": self._gain}
