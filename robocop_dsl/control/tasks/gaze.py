"""The ``gaze`` task: point an axis of a body (a camera's optical axis) at a body."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidParameter
from ..parameters import vector_parameter
from ..spatial import BodyTarget, Current, skew
from ..state import ControlState
from .base import Task
from .body import BodyTask

_AXES = {"x": (1, 2, 0), "y": (2, 0, 1), "z": (0, 1, 2)}
_IDENTITY = np.eye(3)


class GazeTask(BodyTask):
    """Turn ``body`` so that its ``axis`` points at a watched body or point.

    The task value is the pair of components, across the axis, of the unit direction
    from the body's origin to the watched point, in the body's frame [-] (the sines of
    the angles off the axis); the goal is ``(0, 0)``. Only the joints that move
    ``body`` turn it: the watched point's own motion (a part carried by an arm) is
    corrected by the feedback loop, never by moving what is watched.

    Args:
        name: The task's name.
        state: The controller's state.
        body: The body to turn (e.g. ``kinect2_rgb_optical_frame``).
        axis: The body's axis to point, ``x``, ``y`` or ``z`` (optical frames: ``z``).
        **parameters: Those of :class:`BodyTask`; ``target`` is what to look at: a body
            name, a :class:`BodyTarget` (its offset [m] in the reference frame), a point
            [m] in the reference frame, or ``None``/``CURRENT``: nothing (the task then
            asks for no motion).

    Raises:
        InvalidParameter: ``axis`` is not ``x``, ``y`` or ``z``.
    """

    kind = "gaze"

    def __init__(self, name: str, state: ControlState, body: str, axis: str = "z",
                 **parameters):
        if axis not in _AXES:
            raise InvalidParameter(f"gaze '{name}'", "axis", axis, "x, y or z")
        self.axis = axis
        self._rows = np.eye(3)[list(_AXES[axis])]
        self._across = self._rows[:2]
        self._watched = None
        self._found_at: tuple | None = None
        super().__init__(name, state, body, 2, **parameters)

    @property
    def target(self):
        """What the body looks at: a :class:`BodyTarget`, a point [m] or ``None``."""
        return self._watched

    @target.setter
    def target(self, value) -> None:
        if isinstance(value, str):
            value = BodyTarget(value)
        if isinstance(value, BodyTarget):
            self.state.body(value.body)
            if value.offset is not None and not isinstance(value.offset, pin.SE3):
                value = BodyTarget(value.body, self.convert_offset(value.offset))
        elif value is not None and not isinstance(value, Current):
            value = vector_parameter(self.label, "target", value, 3)
        self._watched = None if isinstance(value, Current) else value
        Task.target.fset(self, np.zeros(2))

    def watched_pose(self, state: ControlState) -> pin.SE3 | None:
        """Pose of the watched body (or the watched point, unrotated) in the reference
        frame; ``None`` when nothing is watched."""
        return self.locate(self._watched, lambda frame: state.pose(frame, self.reference_id))

    def locate(self, watched, pose_of) -> pin.SE3 | None:
        """Pose of ``watched`` (a :attr:`target`) in the reference frame, a body's from
        ``pose_of(frame_id)`` (its pose in the reference frame)."""
        if watched is None:
            return None
        if isinstance(watched, BodyTarget):
            return watched.apply(pose_of(self.state.body(watched.body)))
        return pin.SE3(np.eye(3), np.asarray(watched, dtype=float))

    def _direction(self, state: ControlState):
        """``(u, p, d)`` from the body to the watched point (see :func:`direction`),
        computed once per state and target."""
        kinematics = state.kinematics
        stamp, placements, target = kinematics.stamp, kinematics.placements, self._watched
        cached = self._found_at
        if (cached is not None and cached[0] == stamp and cached[1] == placements
                and cached[2] is target):
            return cached[3]
        watched = self.watched_pose(state)
        found = None if watched is None else direction(self.pose(state), watched.translation)
        self._found_at = (stamp, placements, target, found)
        return found

    def compute_value(self, state: ControlState) -> np.ndarray:
        found = self._direction(state)
        return np.zeros(2) if found is None else (self._rows @ found[0])[:2]

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        found = self._direction(state)
        if found is None:
            return np.zeros((2, state.dofs))
        unit, local, distance = found
        rotation_t = self.pose(state).rotation.T
        jacobian = state.jacobian(self.body_id, self.reference_id)
        local_rate = skew(local) @ rotation_t @ jacobian[3:] - rotation_t @ jacobian[:3]
        projection = (_IDENTITY - np.outer(unit, unit)) / distance
        return self._across @ projection @ local_rate

    @property
    def angle(self) -> float:
        """Angle between the axis and the direction to the watched point [rad]; 0 when
        nothing is watched."""
        state = self.state
        if state.kinematics.q is None:
            return 0.0
        watched = self.watched_pose(state)
        return 0.0 if watched is None else self.angle_at(self.pose(state), watched)

    def angle_at(self, pose: pin.SE3, watched: pin.SE3 | None) -> float:
        """:attr:`angle` [rad] with the body at ``pose`` and the watched point at
        ``watched``'s origin (both in the reference frame)."""
        found = None if watched is None else direction(pose, watched.translation)
        if found is None:
            return 0.0
        cosine = float(self._rows[2] @ found[0])
        return math.acos(math.copysign(min(abs(cosine), 1.0), cosine))    # NaN stays NaN

    @property
    def error(self) -> float:
        """The angle off the watched point [rad] (see :attr:`angle`)."""
        return self.angle

    def default_tolerance(self) -> np.ndarray:
        """1 deg [rad] off the watched point."""
        return np.array([np.radians(1.0)])

    def tolerance_errors(self) -> np.ndarray:
        """The :attr:`angle` [rad]."""
        return np.array([self.angle])

    def describe(self) -> str:
        return (f"body={self.body!r}, axis={self.axis!r}, reference={self.reference!r}, "
                f"watching={self._watched!r}, ")

    def parameters(self) -> dict:
        return {**super().parameters(), "target": self._watched, "axis": self.axis}


def direction(pose: pin.SE3, point: np.ndarray):
    """``(u, p, d)``: unit direction [-], vector [m] and distance [m] from the origin of
    ``pose`` to ``point``, in the frame of ``pose``; ``None`` when the point is at the
    origin."""
    local = pose.actInv(point)
    distance = math.sqrt(local.dot(local))
    return None if distance < 1e-9 else (local / distance, local, distance)
