"""Base of the tasks on a body, expressed in a reference body's frame."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidParameter
from ..parameters import vector_parameter
from ..spatial import BodyTarget
from ..state import ControlState
from .base import Task


class BodyTask(Task):
    """A task on ``body``, with values and velocities in the ``reference`` frame.

    Targets may also be a body name or a :class:`BodyTarget`: the tracked body's pose
    in the reference frame is read from the same state every cycle.

    Args:
        name: The task's name.
        state: The controller's state.
        body: The controlled body.
        dimension: Number of task coordinates.
        reference: The body whose frame values are expressed in (default ``world``).
        **parameters: Those of :class:`Task`.
    """

    def __init__(self, name: str, state: ControlState, body: str, dimension: int, *,
                 reference: str = "world", **parameters):
        self.body = body
        self.reference = reference
        self.body_id = state.body(body)
        self.reference_id = 0 if reference == "world" else state.body(reference)
        super().__init__(name, state, dimension, **parameters)

    @property
    def target(self):
        """The target: a value, a body name / :class:`BodyTarget`, or ``CURRENT``."""
        return self._target

    @target.setter
    def target(self, value) -> None:
        if isinstance(value, str):
            value = BodyTarget(value)
        if isinstance(value, BodyTarget):
            if self.order != 0:
                raise InvalidParameter(self.label, "target", value, "a velocity vector")
            self.state.body(value.body)
            if value.offset is not None and not isinstance(value.offset, pin.SE3):
                offset = self.convert_offset(value.offset)
                value = BodyTarget(value.body, offset)
        Task.target.fset(self, value)

    def convert_offset(self, offset) -> np.ndarray:
        """A translation offset [m] as a 3-vector."""
        return vector_parameter(self.label, "target offset", offset, 3)

    def value_from_body(self, state: ControlState, target: BodyTarget):
        pose = target.apply(state.pose(state.body(target.body), self.reference_id))
        return self.value_from_pose(pose)

    def value_from_pose(self, pose: pin.SE3):
        """Hook: the task value of a pose in the reference frame."""
        return pose

    def pose(self, state: ControlState) -> pin.SE3:
        """The body's pose in the reference frame."""
        return state.pose(self.body_id, self.reference_id)

    def _parts(self) -> tuple[bool, bool]:
        """Whether the task has a linear part and an angular part."""
        return self.dimension > len(self.angular_axes), bool(self.angular_axes)

    def default_tolerance(self) -> np.ndarray:
        """1 mm (or 1 mm/s) for the linear part, 1 deg (or 1 deg/s) for the angular
        part, for those the task has."""
        linear, angular = self._parts()
        return np.array([1e-3] * linear + [np.radians(1.0)] * angular)

    def tolerance_errors(self) -> np.ndarray:
        """:attr:`position_error` [m or m/s] and :attr:`orientation_error` [rad or
        rad/s], for the parts the task has."""
        linear, angular = self._parts()
        return np.array([self.position_error] * linear + [self.orientation_error] * angular)

    def describe(self) -> str:
        return f"body={self.body!r}, reference={self.reference!r}, "

    def parameters(self) -> dict:
        return {"body": self.body, "reference": self.reference, **super().parameters()}
