"""The ``body_orientation`` task: turn a body to an orientation."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidParameter
from ..spatial import RotationChart, rotation_error
from ..state import ControlState
from .body import BodyTask


class BodyOrientationTask(BodyTask):
    """Rotation of the body in the reference frame.

    Targets: a 3x3 rotation matrix, a ``pin.Quaternion``, or a pose (its rotation).
    The velocity is the body's angular velocity in the reference axes [rad/s]; the
    error is ``log3(R_target R^T)`` [rad]. Interpolation follows the geodesic.
    """

    kind = "body_orientation"
    angular_axes = (0, 1, 2)

    def __init__(self, name: str, state: ControlState, body: str, **parameters):
        super().__init__(name, state, body, 3, **parameters)

    def convert_target(self, value) -> np.ndarray:
        if isinstance(value, pin.SE3):
            return value.rotation.copy()
        if isinstance(value, pin.Quaternion):
            return value.matrix()
        matrix = np.asarray(value, dtype=float)
        if matrix.shape == (4, 4):
            matrix = matrix[:3, :3]
        if matrix.shape != (3, 3):
            raise InvalidParameter(self.label, "target", value,
                                   "a rotation matrix, quaternion or pose")
        return matrix.copy()

    def chart_for(self, value: np.ndarray) -> RotationChart:
        return RotationChart(value.copy())

    def value_from_pose(self, pose: pin.SE3) -> np.ndarray:
        return pose.rotation

    def compute_value(self, state: ControlState) -> np.ndarray:
        return self.pose(state).rotation

    def compute_error(self, value: np.ndarray, reference: np.ndarray) -> np.ndarray:
        return rotation_error(reference, value)

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return state.jacobian(self.body_id, self.reference_id)[3:]
