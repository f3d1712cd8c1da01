"""The ``otg`` interpolator: online time-optimal trajectories with ruckig."""

from __future__ import annotations

import numpy as np
from ruckig import InputParameter, OutputParameter, Result, Ruckig

from ..parameters import vector_parameter
from .base import Interpolator


class OTGInterpolator(Interpolator):
    """Jerk- (or acceleration-) limited time-optimal trajectory, replanned online.

    Limits are a scalar (every coordinate) or one value per coordinate. For pose and
    orientation tasks the ``max_angular_*`` limits, when given, apply to the rotation
    coordinates [rad/s, rad/s^2, rad/s^3] and the others to the positions.

    Args:
        max_velocity: Maximum velocity [m/s or rad/s].
        max_acceleration: Maximum acceleration [m/s^2 or rad/s^2].
        max_jerk: Maximum jerk [m/s^3 or rad/s^3]; ``None`` for unlimited.
        target_velocity: Velocity to have on reaching the target; ``None`` for rest.
        max_angular_velocity: Rotation coordinates' maximum velocity [rad/s].
        max_angular_acceleration: Rotation coordinates' maximum acceleration [rad/s^2].
        max_angular_jerk: Rotation coordinates' maximum jerk [rad/s^3].
    """

    kind = "otg"

    def __init__(self, max_velocity, max_acceleration, max_jerk=None, target_velocity=None,
                 max_angular_velocity=None, max_angular_acceleration=None,
                 max_angular_jerk=None):
        super().__init__()
        self.limits = {"max_velocity": max_velocity, "max_acceleration": max_acceleration,
                       "max_jerk": max_jerk, "max_angular_velocity": max_angular_velocity,
                       "max_angular_acceleration": max_angular_acceleration,
                       "max_angular_jerk": max_angular_jerk}
        self.target_velocity = target_velocity
        for name, value in self.limits.items():
            if value is not None:
                vector_parameter(self.kind, name, value, np.size(value), minimum=0.0,
                                 strict=True, allow_inf=name.endswith("jerk"))
        self.result = Result.Working
        self._otg = self._input = self._output = None

    def configure_limits(self) -> None:
        size = self.dimension
        self._otg = Ruckig(size, self.time_step)
        self._input = InputParameter(size)
        self._output = OutputParameter(size)
        for name in ("velocity", "acceleration", "jerk"):
            values = self._limit(name, size)
            setattr(self._input, f"max_{name}", values.tolist())
        velocity = np.zeros(size) if self.target_velocity is None else vector_parameter(
            self.kind, "target_velocity", self.target_velocity, size)
        self._input.target_velocity = velocity.tolist()

    def _limit(self, name: str, size: int) -> np.ndarray:
        default = np.inf if name == "jerk" else None
        linear = self.limits[f"max_{name}"]
        linear = default if linear is None else linear
        values = vector_parameter(self.kind, f"max_{name}", linear, size, minimum=0.0,
                                  strict=True, allow_inf=name == "jerk")
        angular = self.limits[f"max_angular_{name}"]
        if angular is not None and self.angular.any():
            count = int(self.angular.sum())
            values[self.angular] = vector_parameter(self.kind, f"max_angular_{name}", angular,
                                                    count, minimum=0.0, strict=True,
                                                    allow_inf=name == "jerk")
        return values

    def start(self) -> None:
        self._input.current_position = self.position.tolist()
        self._input.current_velocity = self.velocity.tolist()
        self._input.current_acceleration = [0.0] * self.dimension
        self.result = Result.Working

    def step(self) -> tuple[np.ndarray, np.ndarray]:
        self._input.target_position = self.target.tolist()
        self.result = self._otg.update(self._input, self._output)
        if self.result in (Result.Working, Result.Finished):
            self._output.pass_to_input(self._input)
            self.position = np.array(self._output.new_position)
            self.velocity = np.array(self._output.new_velocity)
        else:
            self.velocity = np.zeros(self.dimension)
        return self.position, self.velocity

    @property
    def finished(self) -> bool:
        return self.result == Result.Finished

    @property
    def failed(self) -> bool:
        """Whether ruckig rejected the last input (the reference then holds still)."""
        return self.result not in (Result.Working, Result.Finished)

    def parameters(self) -> dict:
        parameters = {key: value for key, value in self.limits.items() if value is not None}
        if self.target_velocity is not None:
            parameters["target_velocity"] = self.target_velocity
        return parameters
