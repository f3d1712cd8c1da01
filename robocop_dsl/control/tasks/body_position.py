"""The ``body_position`` task: move a body's origin to a point."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..state import ControlState
from .body import BodyTask


class BodyPositionTask(BodyTask):
    """Position [m] of the body's origin in the reference frame.

    The velocity is the origin's linear velocity in the reference axes; the error is
    ``target - position``.
    """

    kind = "body_position"

    def __init__(self, name: str, state: ControlState, body: str, **parameters):
        super().__init__(name, state, body, 3, **parameters)

    def convert_target(self, value) -> np.ndarray:
        if isinstance(value, pin.SE3):
            return value.translation.copy()
        return super().convert_target(value)

    def value_from_pose(self, pose: pin.SE3) -> np.ndarray:
        return pose.translation

    def compute_value(self, state: ControlState) -> np.ndarray:
        return self.pose(state).translation

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return state.jacobian(self.body_id, self.reference_id)[:3]
