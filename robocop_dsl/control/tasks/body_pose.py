"""The ``body_pose`` task: bring a body to a pose."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidParameter
from ..spatial import PoseChart, as_pose, pose_error
from ..state import ControlState
from .body import BodyTask


class BodyPoseTask(BodyTask):
    """Pose of the body in the reference frame.

    Targets: a ``pin.SE3`` or a 4x4 homogeneous matrix. The velocity is ``[v, w]``
    (origin's linear and angular velocity, reference axes); the error is the SE(3)
    logarithm of ``T^-1 T_target`` rotated into the reference axes [m, rad].
    ``position_error`` is the distance between the origins [m] and
    ``orientation_error`` the rotation angle between the frames [rad]. Interpolation
    moves the position along a straight line and the rotation along the geodesic.
    """

    kind = "body_pose"
    angular_axes = (3, 4, 5)

    def __init__(self, name: str, state: ControlState, body: str, **parameters):
        super().__init__(name, state, body, 6, **parameters)

    def convert_target(self, value) -> pin.SE3:
        pose = as_pose(value)
        if pose is None:
            raise InvalidParameter(self.label, "target", value, "a pin.SE3 or a 4x4 matrix")
        return pose

    def chart_for(self, value: pin.SE3) -> PoseChart:
        return PoseChart(value)

    def compute_value(self, state: ControlState) -> pin.SE3:
        return self.pose(state)

    def compute_error(self, value: pin.SE3, reference: pin.SE3) -> np.ndarray:
        return pose_error(reference, value)

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return state.jacobian(self.body_id, self.reference_id)

    def _goal_pose(self) -> tuple[pin.SE3, pin.SE3] | None:
        state = self.state
        if state.kinematics.q is None:
            return None
        pose = self.pose(state)
        return pose, self._goal(state, pose)

    @property
    def position_error(self) -> float:
        """Distance [m] between the body's origin and the target's."""
        poses = self._goal_pose()
        if poses is None:
            return float("nan")
        return float(np.linalg.norm(poses[1].translation - poses[0].translation))

    @property
    def orientation_error(self) -> float:
        """Angle [rad] of the rotation from the body to the target."""
        poses = self._goal_pose()
        if poses is None:
            return float("nan")
        return float(np.linalg.norm(pin.log3(poses[0].rotation.T @ poses[1].rotation)))
