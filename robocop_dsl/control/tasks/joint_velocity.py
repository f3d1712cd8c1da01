"""The ``joint_velocity`` task: give a joint group target velocities."""

from __future__ import annotations

import numpy as np

from ..state import ControlState
from .base import Task


class JointVelocityTask(Task):
    """Joint velocities of a group [rad/s or m/s]; the interpolator ramps the target.

    Args:
        name: The task's name.
        state: The controller's state.
        group: The joint group (inside the controlled group).
        **parameters: Those of :class:`Task`.
    """

    kind = "joint_velocity"
    order = 1

    def __init__(self, name: str, state: ControlState, group: str, **parameters):
        self.group, self.columns = state.group_columns(group)
        self._jacobian = np.eye(state.dofs)[self.columns]
        super().__init__(name, state, len(self.columns), **parameters)

    def compute_value(self, state: ControlState) -> np.ndarray:
        return state.velocity[self.columns]

    def compute_jacobian(self, state: ControlState) -> np.ndarray:
        return self._jacobian

    def describe(self) -> str:
        return f"group={self.group.name!r}, "
