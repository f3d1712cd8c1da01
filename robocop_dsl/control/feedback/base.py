"""Abstract feedback loop: turns a task error into a corrective velocity."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np


class FeedbackLoop(ABC):
    """Computes a velocity [unit/s] from a task error, once per control period.

    Attributes:
        dimension: Size of the error.
        time_step: Control period [s].
    """

    kind = "feedback"

    def __init__(self):
        self.dimension = 0
        self.time_step = 0.0

    def setup(self, dimension: int, time_step: float) -> None:
        """Size the loop for a task; called once when attached."""
        self.dimension = dimension
        self.time_step = time_step
        self.validate()
        self.reset()

    def validate(self) -> None:
        """Hook: check the gains against :attr:`dimension`; nothing by default."""

    def reset(self) -> None:
        """Hook: forget the loop's memory (integral, last error); nothing by default."""

    @abstractmethod
    def compute(self, error: np.ndarray) -> np.ndarray:
        """Corrective velocity for ``error`` (task coordinates)."""

    @property
    @abstractmethod
    def gain(self):
        """The proportional gain [1/s] (scalar or per axis)."""

    @gain.setter
    @abstractmethod
    def gain(self, value) -> None:
        """Set the proportional gain."""

    def parameters(self) -> dict:
        """The loop's parameters by name."""
        return {}

    def __repr__(self) -> str:
        arguments = ", ".join(f"{key}={_short(value)}" for key, value in self.parameters().items())
        return f"{self.kind}({arguments})"


def _short(value):
    array = np.asarray(value)
    if array.ndim == 0:
        return repr(float(array))
    if array.size and np.all(array == array.flat[0]):
        return repr(float(array.flat[0]))
    return repr([round(float(v), 6) for v in array])
