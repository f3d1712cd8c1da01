"""The ``otg`` interpolator: online time-optimal trajectories with ruckig."""

from __future__ import annotations

import numpy as np
from ruckig import InputParameter, OutputParameter, Result, Ruckig, RuckigError

from ..parameters import vector_parameter
from .base import Interpolator

ANGULAR_DEFAULTS = {"velocity": 1.0, "acceleration": 2.0, "jerk": np.inf}
"""Rotation limits of a task mixing positions and rotations when no ``max_angular_*``
is given: 1 rad/s, 2 rad/s^2, jerk not limited."""

_LIMITS = ("velocity", "acceleration", "jerk")


class OTGInterpolator(Interpolator):
    """Jerk- (or acceleration-) limited time-optimal trajectory, replanned online.

    Limits are a scalar (every coordinate) or one value per coordinate. On a task
    mixing positions and rotations (``body_pose``, ``body_velocity``) ``max_velocity``,
    ``max_acceleration`` and ``max_jerk`` bound the positions only and the
    ``max_angular_*`` limits the rotation coordinates; those not given are
    :data:`ANGULAR_DEFAULTS` (1 rad/s, 2 rad/s^2, no jerk limit), never the linear
    numbers. On a task of rotations only (``body_orientation``, ``gaze``) the angular
    limits, when given, replace the plain ones.

    A new target (:meth:`retarget`) is followed from the current reference, velocity
    and acceleration. No ruckig failure escapes: a rejected step is retried from the
    state clamped to the velocity limits at zero acceleration; if that fails too, the
    reference holds still (zero velocity) and :attr:`failed` is true until a step
    succeeds.

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
                self._vector(name, value, np.size(value))
        self.result = Result.Working
        self._otg = self._input = self._output = None
        self._max_velocity = np.zeros(0)

    def _vector(self, name: str, value, size: int) -> np.ndarray:
        return vector_parameter(self.kind, name, value, size, minimum=0.0, strict=True,
                                allow_inf=name.endswith("jerk"))

    def configure_limits(self) -> None:
        size = self.dimension
        self._otg = Ruckig(size, self.time_step)
        self._input = InputParameter(size)
        self._output = OutputParameter(size)
        for name in _LIMITS:
            setattr(self._input, f"max_{name}", self.limit(name).tolist())
        self._max_velocity = self.limit("velocity")
        velocity = np.zeros(size) if self.target_velocity is None else vector_parameter(
            self.kind, "target_velocity", self.target_velocity, size)
        self._input.target_velocity = velocity.tolist()

    def limit(self, name: str) -> np.ndarray:
        """The limit ``name`` (``velocity``, ``acceleration``, ``jerk``) of each
        coordinate, as given to ruckig [SI]."""
        linear = self.limits[f"max_{name}"]
        values = self._vector(f"max_{name}", np.inf if linear is None else linear,
                              self.dimension)
        mask = self.angular
        angular = self.limits[f"max_angular_{name}"]
        if not mask.any() or (angular is None and mask.all()):
            return values
        angular = ANGULAR_DEFAULTS[name] if angular is None else angular
        values[mask] = self._vector(f"max_angular_{name}", angular, int(mask.sum()))
        return values

    def start(self) -> None:
        self._input.current_position = self.position.tolist()
        self._input.current_velocity = self.velocity.tolist()
        self._input.current_acceleration = [0.0] * self.dimension
        self.result = Result.Working

    def retarget(self) -> None:
        """Keep the current reference, velocity and acceleration; the next step plans
        towards the new target from them."""
        self.result = Result.Working

    def step(self) -> tuple[np.ndarray, np.ndarray]:
        self._input.target_position = self.target.tolist()
        if not self._update():
            self._clamp()
            if not self._update():
                self._hold()
                return self.position, self.velocity
        self._output.pass_to_input(self._input)
        self.position = np.array(self._output.new_position)
        self.velocity = np.array(self._output.new_velocity)
        return self.position, self.velocity

    def _update(self) -> bool:
        """One ruckig update; ``False`` when ruckig rejects the input."""
        try:
            self.result = self._otg.update(self._input, self._output)
        except (RuckigError, ValueError):
            self.result = Result.Error
        return not self.failed

    def _clamp(self) -> None:
        """The current velocity within its limits [SI], at zero acceleration."""
        velocity = np.clip(self._input.current_velocity, -self._max_velocity,
                           self._max_velocity)
        self._input.current_velocity = velocity.tolist()
        self._input.current_acceleration = [0.0] * self.dimension

    def _hold(self) -> None:
        """The reference stops where it is."""
        self.velocity = np.zeros(self.dimension)
        self._input.current_position = self.position.tolist()
        self._input.current_velocity = self.velocity.tolist()
        self._input.current_acceleration = [0.0] * self.dimension

    @property
    def finished(self) -> bool:
        return self.result == Result.Finished

    @property
    def failed(self) -> bool:
        """Whether ruckig rejected the last step (the reference then holds still)."""
        return self.result not in (Result.Working, Result.Finished)

    def parameters(self) -> dict:
        parameters = {key: value for key, value in self.limits.items() if value is not None}
        if self.target_velocity is not None:
            parameters["target_velocity"] = self.target_velocity
        return parameters
