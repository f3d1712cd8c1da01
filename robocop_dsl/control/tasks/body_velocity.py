"""The ``body_velocity`` task: give a body a target velocity."""

from __future__ import annotations

import numpy as np

from ..state import ControlState
from .body import BodyTask


class BodyVelocityTask(BodyTask):
    """Velocity ``[v, w]`` of the body [m/s, rad/s] in the reference frame's axes.

    ``v`` is the linear velocity of the body's origin. The interpolator ramps the
    target velocity; the measured velocity is the Jacobian times the joint-velocity
    estimate.
    """

    kind = "body_velocity"
    order = 1
    angular_axes = (3, 4, 5)

    def __init__(self, name: str, state: ControlState, body: str, **parameters):
        super().__init__(name, state, body, 6, **parameters)

    def compute_value(self, state: ControlState) -> np.ndarray:
        return self.compute_jacobian(state) @ state.velocity

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return state.jacobian(self.body_id, self.reference_id)
