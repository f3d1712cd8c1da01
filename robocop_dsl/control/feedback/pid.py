"""The ``pid`` feedback loop."""

from __future__ import annotations

import numpy as np

from ..parameters import vector_parameter
from .base import FeedbackLoop


class PIDFeedback(FeedbackLoop):
    """``velocity = kp e + ki integral(e) dt + kd de/dt``.

    The derivative is the finite difference of successive errors (zero on the first
    cycle after a reset).

    Args:
        kp: Proportional gain [1/s], scalar or per axis.
        ki: Integral gain [1/s^2], scalar or per axis.
        kd: Derivative gain [-], scalar or per axis.
        integral_limit: Bound on each integral component [unit s]; ``None`` for none.
    """

    kind = "pid"

    def __init__(self, kp=1.0, ki=0.0, kd=0.0, integral_limit=None):
        super().__init__()
        self._gains = {"kp": kp, "ki": ki, "kd": kd}
        for name, value in self._gains.items():
            vector_parameter(self.kind, name, value, np.size(value), minimum=0.0)
        self.integral_limit = integral_limit
        self.integral = np.zeros(0)
        self.last_error: np.ndarray | None = None

    def validate(self) -> None:
        for name, value in self._gains.items():
            self._gains[name] = vector_parameter(self.kind, name, value, self.dimension,
                                                 minimum=0.0)
        if self.integral_limit is not None:
            self.integral_limit = vector_parameter(self.kind, "integral_limit",
                                                   self.integral_limit, self.dimension,
                                                   minimum=0.0)

    def reset(self) -> None:
        self.integral = np.zeros(self.dimension)
        self.last_error = None

    def compute(self, error: np.ndarray) -> np.ndarray:
        self.integral = self.integral + error * self.time_step
        if self.integral_limit is not None:
            self.integral = np.clip(self.integral, -self.integral_limit, self.integral_limit)
        derivative = (np.zeros(self.dimension) if self.last_error is None
                      else (error - self.last_error) / self.time_step)
        self.last_error = error.copy()
        gains = self._gains
        return gains["kp"] * error + gains["ki"] * self.integral + gains["kd"] * derivative

    @property
    def gain(self):
        return self._gains["kp"]

    @gain.setter
    def gain(self, value) -> None:
        self._gains["kp"] = vector_parameter(self.kind, "kp", value, self.dimension or 1,
                                             minimum=0.0)

    def parameters(self) -> dict:
        parameters = dict(self._gains)
        if self.integral_limit is not None:
            parameters["integral_limit"] = self.integral_limit
        return parameters
